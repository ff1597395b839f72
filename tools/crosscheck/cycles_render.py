# Renders a nuld scene file in Blender's Cycles, matching nuld's conventions,
# for the cross-check (README.md in this folder). Run by Blender:
#   blender -b --factory-startup -P cycles_render.py -- SCENE.json ASSETS OUT.exr SPP SEED
# Only what the cross-check scenes use is translated: camera, film, max depth,
# the environment (file, scale, rotation, up), Lambertian and Disney materials
# and the built-in shapes (floor, sphere); anything else is refused.
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector


def fail(message):
    print(f"cycles_render: {message}", file=sys.stderr)
    sys.exit(2)


def to_blender(v):
    # nuld is +Y up and right-handed; Blender is +Z up: (x, y, z) -> (x, -z, y),
    # a proper rotation, so handedness is kept.
    return Vector((v[0], -v[2], v[1]))


def sphere_mesh(center, radius, rings=64, segments=128):
    # The same vertices, normals and triangles as nuld's makeSphere
    # (renderer/shapes.cpp), so both renderers trace the same tessellation.
    verts, normals, faces = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            verts.append(to_blender([center[k] + radius * n[k] for k in range(3)]))
            normals.append(to_blender(n))
    ident = lambda r, s: r * (segments + 1) + s
    for r in range(rings):
        for s in range(segments):
            if r > 0:  # nuld keeps the poles' degenerate triangles; they have no area
                faces.append((ident(r, s), ident(r, s + 1), ident(r + 1, s)))
            if r < rings - 1:
                faces.append((ident(r, s + 1), ident(r + 1, s + 1), ident(r + 1, s)))
    return verts, normals, faces


def floor_mesh(half, height):
    p = [(-half, height, -half), (half, height, -half), (half, height, half), (-half, height, half)]
    return [to_blender(v) for v in p], [to_blender((0, 1, 0))] * 4, [(0, 2, 1), (0, 3, 2)]


def add_mesh(name, verts, normals, faces, material):
    # Smooth shading with Blender's own vertex normals (area-weighted face
    # normals), which on these shapes are the normals nuld interpolates. Handing
    # nuld's normals over as custom split normals instead made Cycles' sphere
    # 1-3 % darker in places (not understood; README.md in this folder).
    del normals
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = True
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(material)
    bpy.context.scene.collection.objects.link(obj)


def make_material(name, spec):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    kind = spec.get("type", "disney")
    if kind == "lambertian":
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*spec.get("albedo", [0.5] * 3), 1)
        bsdf.inputs["Roughness"].default_value = 0
    elif kind == "disney":
        # Principled is Disney-like, not Disney: Cycles uses dielectric Fresnel
        # and separable Smith (README.md in this folder lists the differences).
        bsdf = nodes.new("ShaderNodeBsdfPrincipled")
        bsdf.inputs["Base Color"].default_value = (*spec.get("base_color", [0.8] * 3), 1)
        for key, socket in [("metallic", "Metallic"), ("roughness", "Roughness"),
                            ("specular", "Specular"), ("specular_tint", "Specular Tint"),
                            ("anisotropic", "Anisotropic"), ("sheen", "Sheen"),
                            ("sheen_tint", "Sheen Tint"), ("clearcoat", "Clearcoat"),
                            ("clearcoat_gloss", "Clearcoat Roughness"),
                            ("subsurface", "Subsurface")]:
            if key in spec:
                value = spec[key]
                if key == "clearcoat_gloss":
                    value = 1 - value  # gloss 1 is the sharpest coat
                bsdf.inputs[socket].default_value = value
    else:
        fail(f"material '{name}': type '{kind}' is not translated")
    mat.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def build_world(env, assets):
    world = bpy.data.worlds.new("nuld")
    bpy.context.scene.world = world
    world.use_nodes = True
    nodes = world.node_tree.nodes
    nodes.clear()
    coords = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    # nuld's lat-long: u = 0 faces -Z (Blender +Y), u = 1/4 faces +X; Cycles'
    # equirectangular: u = 1/4 faces +Y, 1/2 faces +X. nuld turns the map by
    # `rotation` about +Z (Blender's axes) and then tilts it to `up`, so the
    # lookup undoes the tilt, undoes the turn and adds the quarter turn.
    up = env.get("up", [0, 1, 0])
    if up != [0, 1, 0]:
        if up != [0, -1, 0]:
            fail("environment.up: only [0, 1, 0] and [0, -1, 0] are translated")
        tilt = Matrix.Rotation(math.pi, 4, "X")  # nuld's half-turn about +X
    else:
        tilt = Matrix.Identity(4)
    turn = Matrix.Rotation(math.radians(90 - env.get("rotation", 0)), 4, "Z")
    # The mapping rotates the lookup direction: world -> map frame.
    mapping.inputs["Rotation"].default_value = (turn @ tilt.inverted()).to_euler("XYZ")
    tex = nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(os.path.join(assets, env["file"]))
    tex.interpolation = "Closest"  # nuld's map is piecewise constant per texel
    background = nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = env.get("scale", 1)
    out = nodes.new("ShaderNodeOutputWorld")
    links = world.node_tree.links
    links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    links.new(tex.outputs["Color"], background.inputs["Color"])
    links.new(background.outputs["Background"], out.inputs["Surface"])


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 5:
        fail("usage: -- SCENE.json ASSETS OUT.exr SPP SEED")
    scene_path, assets, out_path, spp, seed = argv
    with open(scene_path) as f:
        spec = json.load(f)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = int(spp)
    cycles.seed = int(seed)
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.sample_clamp_direct = 0
    cycles.sample_clamp_indirect = 0
    cycles.blur_glossy = 0
    cycles.light_sampling_threshold = 0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    depth = spec.get("render", {}).get("max_depth", 5)
    # nuld's max depth d counts hits; Cycles counts bounces after the first.
    for attr in ["max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "transparent_max_bounces", "volume_bounces"]:
        setattr(cycles, attr, depth - 1)
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    film = spec.get("film", {})
    scene.render.resolution_x = film.get("width", 512)
    scene.render.resolution_y = film.get("height", 512)
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = out_path

    cam = spec["camera"]
    if cam.get("mirror_x", False):
        fail("camera.mirror_x is not translated")
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL" if scene.render.resolution_y < scene.render.resolution_x \
        else "HORIZONTAL"
    cam_data.angle = math.radians(cam.get("fov", 40))  # nuld's fov spans the shorter side
    cam_obj = bpy.data.objects.new("camera", cam_data)
    eye, target = to_blender(cam["eye"]), to_blender(cam["look_at"])
    up = to_blender(cam.get("up", [0, 1, 0]))
    forward = (target - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rot = Matrix((right, true_up, -forward)).transposed()  # columns: camera x, y, z
    cam_obj.matrix_world = Matrix.Translation(eye) @ rot.to_4x4()
    scene.collection.objects.link(cam_obj)
    scene.camera = cam_obj

    if "environment" in spec:
        build_world(spec["environment"], assets)
    materials = {name: make_material(name, m) for name, m in spec.get("materials", {}).items()}
    for k, entry in enumerate(spec["meshes"]):
        shape = entry.get("shape")
        if shape == "floor":
            data = floor_mesh(entry.get("half_size", 20), entry.get("height", 0))
        elif shape == "sphere":
            data = sphere_mesh(entry.get("center", [0, 0, 0]), entry.get("radius", 1))
        else:
            fail(f"meshes[{k}]: only the built-in shapes are translated")
        add_mesh(f"{shape}{k}", *data, materials[entry["material"]])
    bpy.ops.render.render(write_still=True)


main()
