# Renders a nuld scene file in Blender's Cycles, matching nuld's conventions,
# for the cross-check (README.md in this folder). Run by Blender:
#   blender -b --factory-startup -P cycles_render.py -- SCENE.json ASSETS OUT.exr SPP SEED
# Only what the cross-check scenes use is translated: camera, film, max depth,
# the environment (file, scale, rotation, up), Lambertian and Disney materials,
# the built-in shapes (floor, sphere), emitters (rectangle, sphere) and
# emitting meshes of those shapes; anything else is refused. SCENE may also
# be the name of nuld's built-in `cornell` or `veach-mis`, rebuilt here from
# the numbers of scenes/cornell_scene.cpp and scenes/veach_mis_scene.cpp.
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import configure_cycles, write_exr  # noqa: E402


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


def quad_mesh(corner, a, b):
    # corner + [0, 1] a + [0, 1] b, wound so that cross(a, b) is its normal.
    c = [corner, [corner[k] + a[k] for k in range(3)],
         [corner[k] + a[k] + b[k] for k in range(3)], [corner[k] + b[k] for k in range(3)]]
    return [to_blender(v) for v in c], None, [(0, 1, 2), (0, 2, 3)]


def box_mesh(c, X, Y, Z):
    # Mitsuba's cube [-1, 1]^3 under x -> c + X x.x + Y x.y + Z x.z, faces outward.
    verts = []
    for k in range(8):
        s = [1 if k & 1 else -1, 1 if k & 2 else -1, 1 if k & 4 else -1]
        verts.append(to_blender([c[i] + s[0] * X[i] + s[1] * Y[i] + s[2] * Z[i]
                                 for i in range(3)]))
    faces = []
    for f in [(0, 2, 6, 4), (1, 5, 7, 3), (0, 4, 5, 1), (2, 3, 7, 6), (0, 1, 3, 2), (4, 6, 7, 5)]:
        faces += [(f[0], f[1], f[2]), (f[0], f[2], f[3])]
    return verts, None, faces


def add_mesh(name, verts, normals, faces, material, smooth=True):
    # Smooth shading with Blender's own vertex normals (area-weighted face
    # normals), which on these shapes are the normals nuld interpolates. Handing
    # nuld's normals over as custom split normals instead made Cycles' sphere
    # 1-3 % darker in places (not understood; README.md in this folder).
    del normals
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = smooth
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
        bsdf.distribution = "GGX"  # single scattering, as nuld's Disney BRDF
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


def emission_material(name, radiance, two_sided=False, surface=None):
    # A constant radiance (Cycles' emission closure of strength 1 is radiance),
    # added to the surface's own BSDF if it has one. One-sided, as nuld's
    # lights are by default: the back face (Backfacing = 1) emits nothing.
    mat = surface or bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    if surface is None:
        nodes.clear()  # a new material's default Principled BSDF would reflect
    out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL"), None)
    if out is None:
        out = nodes.new("ShaderNodeOutputMaterial")
    previous = out.inputs["Surface"].links[0].from_socket if out.inputs["Surface"].links else None
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs["Color"].default_value = (*scaled(radiance, 1), 1)
    emit.inputs["Strength"].default_value = 1
    shader = emit.outputs["Emission"]
    if not two_sided:
        geometry = nodes.new("ShaderNodeNewGeometry")
        mix = nodes.new("ShaderNodeMixShader")
        links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
        links.new(emit.outputs["Emission"], mix.inputs[1])  # front: the emission
        shader = mix.outputs["Shader"]  # back: an empty shader (no light)
    if previous is not None:
        add = nodes.new("ShaderNodeAddShader")
        links.new(previous, add.inputs[0])
        links.new(shader, add.inputs[1])
        shader = add.outputs["Shader"]
    links.new(shader, out.inputs["Surface"])
    return mat


def lambertian(name, rgb):
    return make_material(name, {"type": "lambertian", "albedo": list(rgb)})


def scaled(radiance, scale):
    rgb = radiance if isinstance(radiance, list) else [radiance] * 3
    return [v * scale for v in rgb]


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


def build_cornell():
    # scenes/cornell_scene.cpp: Mitsuba 3's Cornell box.
    white = lambertian("white", (0.885809, 0.698859, 0.666422))
    red = lambertian("red", (0.570068, 0.0430135, 0.0443706))
    green = lambertian("green", (0.105421, 0.37798, 0.076425))
    for name, c, a, b, m in [("floor", [-1, -1, -1], [0, 0, 2], [2, 0, 0], white),
                             ("ceiling", [-1, 1, -1], [2, 0, 0], [0, 0, 2], white),
                             ("back", [-1, -1, -1], [2, 0, 0], [0, 2, 0], white),
                             ("red-wall", [-1, -1, -1], [0, 2, 0], [0, 0, 2], red),
                             ("green-wall", [1, -1, -1], [0, 0, 2], [0, 2, 0], green)]:
        add_mesh(name, *quad_mesh(c, a, b), m, smooth=False)
    add_mesh("small-box", *box_mesh([0.335, -0.7, 0.38], [0.286891, 0, 0.0877115], [0, 0.3, 0],
                                    [-0.0877115, 0, 0.286891]), white, smooth=False)
    add_mesh("large-box", *box_mesh([-0.33, -0.4, -0.28], [0.28491, 0, -0.0939491], [0, 0.61, 0],
                                    [0.0939491, 0, 0.28491]), white, smooth=False)
    light = emission_material("light", [18.387, 13.9873, 6.75357])
    add_mesh("light", *quad_mesh([-0.23, 0.99, -0.18], [0.46, 0, 0], [0, 0, 0.38]), light,
             smooth=False)
    return {"camera": {"eye": [0, 0, 3.9], "look_at": [0, 0, 0], "fov": 39.3077},
            "film": {"width": 256, "height": 256}, "render": {"max_depth": 8}}


def build_veach_mis():
    # scenes/veach_mis_scene.cpp: Mitsuba 0.5's veach_mi numbers, Disney
    # metal plates (Principled, GGX alpha = roughness^2), grey floor and wall.
    for k, (y0, z0, y1, z1, alpha) in enumerate(
            [(-2.70651, 0.25609, -2.08375, -0.526323, 0.005),
             (-3.28825, 1.36972, -2.83856, 0.476536, 0.02),
             (-3.73096, 2.70046, -3.43378, 1.74564, 0.05),
             (-3.99615, 4.0667, -3.82069, 3.08221, 0.1)]):
        metal = make_material(f"plate{k + 1}", {"type": "disney", "base_color": [0.8] * 3,
                                                 "metallic": 1, "roughness": math.sqrt(alpha)})
        add_mesh(f"plate{k + 1}", *quad_mesh([4, y0, z0], [0, y1 - y0, z1 - z0], [-8, 0, 0]),
                 metal, smooth=False)
    grey = lambertian("grey", (0.4, 0.4, 0.4))
    add_mesh("floor", *quad_mesh([-10, -4.1, -10], [0, 0, 20], [20, 0, 0]), grey, smooth=False)
    add_mesh("wall", *quad_mesh([-10, -4.1, -2], [20, 0, 0], [0, 14.1, 0]), grey, smooth=False)
    for k, (centre, radius, radiance) in enumerate(
            [([-3.75, 0, 0], 0.03333, 901.803), ([-1.25, 0, 0], 0.1, 100),
             ([1.25, 0, 0], 0.3, 11.1111), ([3.75, 0, 0], 0.9, 1.23457),
             ([10, 10, 4], 0.5, 800)]):
        add_mesh(f"light{k}", *sphere_mesh(centre, radius),
                 emission_material(f"light{k}", radiance))
    fov = 2 * math.degrees(math.atan(math.tan(math.radians(12.5)) * 512 / 768))
    return {"camera": {"eye": [0, 6, 27.5], "look_at": [0, -1.5, 2.5], "fov": fov},
            "film": {"width": 768, "height": 512}, "render": {"max_depth": 1}}


BUILT_IN = {"cornell": build_cornell, "veach-mis": build_veach_mis}


def build_file_scene(spec, assets):
    if "environment" in spec:
        build_world(spec["environment"], assets)
    materials = {name: make_material(name, m) for name, m in spec.get("materials", {}).items()}
    for k, entry in enumerate(spec.get("meshes", [])):
        shape = entry.get("shape")
        if shape == "floor":
            data = floor_mesh(entry.get("half_size", 20), entry.get("height", 0))
        elif shape == "sphere":
            data = sphere_mesh(entry.get("center", [0, 0, 0]), entry.get("radius", 1))
        else:
            fail(f"meshes[{k}]: only the built-in shapes are translated")
        material = materials[entry["material"]]
        if "emission" in entry:
            e = entry["emission"]
            material = emission_material(f"emission{k}", scaled(e["radiance"], e.get("scale", 1)),
                                         e.get("two_sided", False), material.copy())
        add_mesh(f"{shape}{k}", *data, material)
    for k, e in enumerate(spec.get("emitters", [])):
        mat = emission_material(f"emitter{k}", scaled(e["radiance"], e.get("scale", 1)),
                                e.get("two_sided", False))
        if e["shape"] == "rectangle":
            add_mesh(f"emitter{k}", *quad_mesh(e["corner"], e["edge0"], e["edge1"]), mat,
                     smooth=False)
        elif e["shape"] == "sphere":
            add_mesh(f"emitter{k}", *sphere_mesh(e["center"], e["radius"]), mat)
        else:
            fail(f"emitters[{k}]: shape '{e['shape']}' is not translated")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 5:
        fail("usage: -- SCENE.json ASSETS OUT.exr SPP SEED")
    scene_path, assets, out_path, spp, seed = argv
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if scene_path in BUILT_IN:
        spec = BUILT_IN[scene_path]()
    else:
        with open(scene_path) as f:
            spec = json.load(f)
        build_file_scene(spec, assets)
    scene = bpy.context.scene
    configure_cycles(scene, spp, seed, spec.get("render", {}).get("max_depth", 5))
    film = spec.get("film", {})
    scene.render.resolution_x = film.get("width", 512)
    scene.render.resolution_y = film.get("height", 512)
    scene.render.resolution_percentage = 100
    write_exr(scene, out_path)

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

    bpy.ops.render.render(write_still=True)


main()
