# A scene made in Blender, exported by Blender's own glTF exporter, and
# rendered by Cycles: the other half of nuld's glTF cross-check
# (gltf_crosscheck.sh, README.md here). Run by Blender:
#   blender -b --factory-startup -P gltf_blender.py -- OUT.glb OUT.exr SPP SEED
# A textured Principled floor, a Principled sphere, a metal box, an emissive
# panel, a point light of radius 0 and a sun of angle 0, no world light.
# Lights are exported in the exporter's "Unitless" mode (COMPAT): a point
# light of P W as P / (4 pi) per steradian and a sun of S W/m^2 as S, the
# radiant intensity and irradiance Cycles gives them, which nuld reads as
# such (docs/usage.md). Blender's default "Standard" mode multiplies point
# and spot intensities by 683 lm/W but writes emission strengths unscaled.
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import configure_cycles, write_exr  # noqa: E402

SIZE = (512, 384)


def fail(message):
    print("gltf_blender.py: " + message, file=sys.stderr)
    sys.exit(1)


def principled(name, base, roughness, metallic=0.0, texture=None):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.distribution = "GGX"  # single scattering, as nuld's Disney BRDF
    bsdf.inputs["Base Color"].default_value = (*base, 1)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Specular"].default_value = 0.5
    if texture is not None:
        node = mat.node_tree.nodes.new("ShaderNodeTexImage")
        node.image = texture
        node.interpolation = "Linear"
        mat.node_tree.links.new(node.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def emissive(name, colour, strength):
    mat = principled(name, (0, 0, 0), 1.0)
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Emission"].default_value = (*colour, 1)
    bsdf.inputs["Emission Strength"].default_value = strength
    bsdf.inputs["Specular"].default_value = 0.0
    return mat


# Cycles filters an 8-bit texture before decoding it from sRGB, nuld (and
# GPUs' sRGB textures) after: they differ where texels change, so the cells
# are 64 texels wide and their one-texel edges a small share of the floor.
def checker_image(n=512, cells=8):
    img = bpy.data.images.new("checker", n, n, alpha=False)
    s = n // cells
    pixels = []
    for y in range(n):
        for x in range(n):
            v = 0.8 if ((x // s) + (y // s)) % 2 == 0 else 0.2
            pixels += [v, v, v, 1.0]
    img.pixels = pixels
    img.filepath_raw = bpy.app.tempdir + "checker.png"
    img.file_format = "PNG"
    img.save()
    img.pack()
    return img


def add(obj, material):
    obj.data.materials.append(material)
    return obj


def build():
    bpy.ops.mesh.primitive_plane_add(size=6, location=(0, 0, 0))
    add(bpy.context.object, principled("floor", (1, 1, 1), 0.7, texture=checker_image()))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(0.9, 0.2, 0.6), segments=96,
                                         ring_count=48)
    bpy.ops.object.shade_smooth()
    add(bpy.context.object, principled("clay", (0.8, 0.35, 0.2), 0.5))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(-0.9, -0.3, 0.4),
                                    rotation=(0, 0, math.radians(25)))
    add(bpy.context.object, principled("metal", (0.9, 0.7, 0.4), 0.35, metallic=1.0))
    # An emissive panel above, facing down (a plane faces +z; turned over).
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0, 0, 2.4), rotation=(math.pi, 0, 0))
    add(bpy.context.object, emissive("panel", (1.0, 0.9, 0.8), 6.0))
    point = bpy.data.lights.new("point", "POINT")
    point.energy = 150.0
    point.shadow_soft_size = 0.0
    obj = bpy.data.objects.new("point", point)
    obj.location = (1.8, -1.5, 2.0)
    bpy.context.scene.collection.objects.link(obj)
    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = 1.5
    sun.angle = 0.0
    obj = bpy.data.objects.new("sun", sun)
    obj.rotation_euler = (math.radians(35), 0, math.radians(30))
    bpy.context.scene.collection.objects.link(obj)
    cam = bpy.data.cameras.new("camera")
    cam.angle = math.radians(50)
    cam.sensor_fit = "AUTO"
    obj = bpy.data.objects.new("camera", cam)
    obj.location = (0, -5.0, 2.6)
    direction = Vector((0, 0, 0.4)) - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    bpy.context.scene.world = world


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 4:
        fail("usage: -- OUT.glb OUT.exr SPP SEED")
    glb, exr, spp, seed = argv
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build()
    scene = bpy.context.scene
    # Before the export: the exporter writes the camera's aspect ratio from it.
    scene.render.resolution_x, scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    bpy.ops.export_scene.gltf(filepath=glb, export_format="GLB", export_cameras=True,
                              export_lights=True, convert_lighting_mode="COMPAT",
                              export_yup=True, export_apply=True)
    configure_cycles(scene, spp, seed, 5)  # nuld's glTF scenes trace 5 hits
    write_exr(scene, exr)
    bpy.ops.render.render(write_still=True)


main()
