#!/usr/bin/env python3
"""Writes nuld's glTF 2.0 test scene from nothing but this script.

    make_test_scene.py OUT.gltf|OUT.glb [--lights all|point|spot|directional|emissive]

A textured floor, a box under a rotated and scaled parent node, a metal
sphere with a metallic-roughness texture, a glass slab (transmission, ior),
a clear-coated sphere, an emissive panel, a point, a spot and a directional
light, and a perspective camera, with buffers and PNG textures embedded
(base64 in .gltf, the binary chunk in .glb). It also holds what nuld names
as unused: a normal texture, a sheen extension and an orthographic camera.
`--lights` keeps one kind of light only, for tests that check one. Only the
standard library: the PNGs are written here too.
"""

import argparse
import base64
import json
import math
import os
import struct
import sys
import zlib


def png(width, height, rgb_rows):
    """An 8-bit RGB PNG of rows of (r, g, b) bytes."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rgb_rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def checker(n, cells, a, b):
    s = n // cells
    return png(n, n, [[a if ((x // s) + (y // s)) % 2 == 0 else b for x in range(n)]
                      for y in range(n)])


class Builder:
    """Accumulates one buffer and the accessors and views into it."""

    def __init__(self):
        self.data = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "nuld tools/gltf/make_test_scene.py"},
                    "buffers": [], "bufferViews": [], "accessors": [], "meshes": [],
                    "materials": [], "nodes": [], "images": [], "textures": [],
                    "samplers": [{"wrapS": 10497, "wrapT": 10497}], "cameras": []}

    def view(self, blob):
        while len(self.data) % 4:
            self.data.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.data),
                                        "byteLength": len(blob)})
        self.data += blob
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, kind, component, fmt):
        flat = [c for v in values for c in (v if isinstance(v, (list, tuple)) else [v])]
        acc = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat)),
               "componentType": component, "count": len(values), "type": kind}
        if kind == "VEC3":
            acc["min"] = [min(v[k] for v in values) for k in range(3)]
            acc["max"] = [max(v[k] for v in values) for k in range(3)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def mesh(self, name, positions, normals, uvs, indices, material):
        attributes = {"POSITION": self.accessor(positions, "VEC3", 5126, "f"),
                      "NORMAL": self.accessor(normals, "VEC3", 5126, "f")}
        if uvs:
            attributes["TEXCOORD_0"] = self.accessor(uvs, "VEC2", 5126, "f")
        self.doc["meshes"].append({"name": name, "primitives": [{
            "attributes": attributes, "indices": self.accessor(indices, "SCALAR", 5125, "I"),
            "material": material}]})
        return len(self.doc["meshes"]) - 1

    def image(self, name, blob):
        self.doc["images"].append({"name": name, "mimeType": "image/png",
                                   "bufferView": self.view(blob)})
        self.doc["textures"].append({"source": len(self.doc["images"]) - 1, "sampler": 0})
        return len(self.doc["textures"]) - 1

    def material(self, m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def node(self, n):
        self.doc["nodes"].append(n)
        return len(self.doc["nodes"]) - 1


def quad(half_x, half_z, uv_scale):
    p = [(-half_x, 0, -half_z), (-half_x, 0, half_z), (half_x, 0, half_z), (half_x, 0, -half_z)]
    uv = [(0, 0), (0, uv_scale), (uv_scale, uv_scale), (uv_scale, 0)]
    return p, [(0, 1, 0)] * 4, uv, [0, 1, 2, 0, 2, 3]


def box(half):
    positions, normals, uvs, indices = [], [], [], []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = [0, 0, 0]
            v[(axis + 2) % 3] = 1
            if sign < 0:
                u, v = v, u  # keep the winding counter-clockwise seen from outside
            base = len(positions)
            for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append(tuple(half * (n[k] + su * u[k] + sv * v[k]) for k in range(3)))
                normals.append(tuple(n))
                uvs.append(((su + 1) / 2, (sv + 1) / 2))
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, uvs, indices


def sphere(radius, rows=24, cols=48):
    positions, normals, uvs, indices = [], [], [], []
    for i in range(rows + 1):
        theta = math.pi * i / rows
        for j in range(cols + 1):
            phi = 2 * math.pi * j / cols
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            positions.append(tuple(radius * c for c in n))
            normals.append(n)
            uvs.append((j / cols, i / rows))
    for i in range(rows):
        for j in range(cols):
            a, b = i * (cols + 1) + j, (i + 1) * (cols + 1) + j
            indices += [a, b, a + 1, a + 1, b, b + 1]
    return positions, normals, uvs, indices


def look_rotation(eye, target):
    """The quaternion (x, y, z, w) turning -z towards target, +y kept up."""
    f = [t - e for t, e in zip(target, eye)]
    fl = math.sqrt(sum(c * c for c in f))
    z = [-c / fl for c in f]  # the camera's +z points backwards
    x = [z[2], 0, -z[0]]  # up x z, up = +y
    xl = math.sqrt(sum(c * c for c in x))
    x = [c / xl for c in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    w = math.sqrt(max(0.0, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    return [(m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w),
            (m[1][0] - m[0][1]) / (4 * w), w]


def build(lights):
    b = Builder()
    floor_tex = b.image("checker", checker(64, 8, (204, 204, 204), (51, 51, 51)))
    mr_tex = b.image("metal-roughness", png(2, 2, [[(0, 128, 255), (0, 255, 255)],
                                                 [(0, 64, 255), (0, 200, 255)]]))
    floor_m = b.material({"name": "floor", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": floor_tex}, "metallicFactor": 0, "roughnessFactor": 0.8},
        "normalTexture": {"index": floor_tex}})
    box_m = b.material({"name": "clay", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.3, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.6},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}}})
    metal_m = b.material({"name": "metal", "pbrMetallicRoughness": {
        "baseColorFactor": [0.95, 0.7, 0.4, 1], "metallicFactor": 1, "roughnessFactor": 0.6,
        "metallicRoughnessTexture": {"index": mr_tex}}})
    glass_m = b.material({"name": "glass", "pbrMetallicRoughness": {
        "metallicFactor": 0, "roughnessFactor": 0},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                       "KHR_materials_ior": {"ior": 1.5}}})
    coat_m = b.material({"name": "coated", "pbrMetallicRoughness": {
        "baseColorFactor": [0.1, 0.2, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
                                                   "clearcoatRoughnessFactor": 0.1},
                       "KHR_materials_specular": {"specularFactor": 0.8}}})
    lamp_m = b.material({"name": "lamp", "emissiveFactor": [1, 0.9, 0.8],
                         "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
                         "extensions": {"KHR_materials_emissive_strength":
                                        {"emissiveStrength": 8}}})

    roots = []
    roots.append(b.node({"name": "floor", "mesh": b.mesh("floor", *quad(3, 3, 3), floor_m)}))
    # A box placed through a hierarchy: the parent turns and scales, the child moves.
    child = b.node({"name": "box", "mesh": b.mesh("box", *box(0.5), box_m),
                    "translation": [0, 0.5, 0]})
    roots.append(b.node({"name": "box-parent", "children": [child], "translation": [-1.1, 0, -0.4],
                         "rotation": [0, math.sin(math.radians(15)), 0,
                                      math.cos(math.radians(15))], "scale": [0.8, 0.8, 0.8]}))
    roots.append(b.node({"name": "metal", "mesh": b.mesh("metal-ball", *sphere(0.45), metal_m),
                         "translation": [0.3, 0.45, -0.8]}))
    roots.append(b.node({"name": "coated", "mesh": b.mesh("coated-ball", *sphere(0.35), coat_m),
                         "translation": [1.3, 0.35, 0.2]}))
    roots.append(b.node({"name": "glass", "mesh": b.mesh("glass-slab", *box(0.3), glass_m),
                         "translation": [0.0, 0.3, 0.7], "scale": [1.2, 1.0, 0.3]}))
    light_defs = {
        "point": {"type": "point", "color": [1, 0.95, 0.9], "intensity": 6},
        "spot": {"type": "spot", "color": [0.9, 0.95, 1], "intensity": 12,
                 "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}},
        "directional": {"type": "directional", "color": [1, 1, 1], "intensity": 1.5},
    }
    kept = [k for k in light_defs if lights in ("all", k)]
    if kept:
        b.doc["extensionsUsed"] = ["KHR_lights_punctual"]
        b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [light_defs[k] for k in kept]}}
    places = {"point": {"translation": [1.5, 2.0, 1.0]},
              "spot": {"translation": [-1.5, 2.5, 1.5],
                       "rotation": look_rotation([-1.5, 2.5, 1.5], [-0.8, 0, -0.2])},
              "directional": {"rotation": look_rotation([0, 0, 0], [0.3, -1, -0.4])}}
    for i, k in enumerate(kept):
        roots.append(b.node({"name": k + "-light", **places[k],
                             "extensions": {"KHR_lights_punctual": {"light": i}}}))
    if lights in ("all", "emissive"):
        panel = quad(0.6, 0.4, 1)
        roots.append(b.node({"name": "lamp", "mesh": b.mesh("lamp", panel[0],
                                                            [(0, -1, 0)] * 4, panel[2],
                                                            [0, 2, 1, 0, 3, 2], lamp_m),
                             "translation": [0, 2.6, 0]}))
    b.doc["cameras"] = [{"name": "view", "type": "perspective",
                         "perspective": {"yfov": 0.75, "aspectRatio": 1.5, "znear": 0.1}},
                        {"name": "plan", "type": "orthographic",
                         "orthographic": {"xmag": 3, "ymag": 3, "znear": 0.1, "zfar": 100}}]
    eye = [0, 1.6, 4.2]
    roots.append(b.node({"name": "camera", "camera": 0, "translation": eye,
                         "rotation": look_rotation(eye, [0, 0.45, 0])}))
    roots.append(b.node({"name": "plan-camera", "camera": 1, "translation": [0, 5, 0],
                         "rotation": [-math.sqrt(0.5), 0, 0, math.sqrt(0.5)]}))
    used = ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_clearcoat",
            "KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_materials_sheen"]
    b.doc["extensionsUsed"] = b.doc.get("extensionsUsed", []) + used
    b.doc["scenes"] = [{"nodes": roots}]
    b.doc["scene"] = 0
    return b


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="the file to write: .gltf (JSON, data embedded) or .glb")
    parser.add_argument("--lights", default="all",
                        choices=["all", "point", "spot", "directional", "emissive"])
    args = parser.parse_args()
    b = build(args.lights)
    while len(b.data) % 4:
        b.data.append(0)
    if args.out.endswith(".glb"):
        b.doc["buffers"] = [{"byteLength": len(b.data)}]
        text = json.dumps(b.doc, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        body = (struct.pack("<II", len(text), 0x4E4F534A) + text
                + struct.pack("<II", len(b.data), 0x004E4942) + bytes(b.data))
        blob = struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body
    elif args.out.endswith(".gltf"):
        b.doc["buffers"] = [{"byteLength": len(b.data), "uri": "data:application/octet-stream;"
                             "base64," + base64.b64encode(bytes(b.data)).decode()}]
        blob = json.dumps(b.doc, indent=1).encode()
    else:
        sys.exit("make_test_scene.py: %s: expected a .gltf or .glb file name" % args.out)
    # Written under a temporary name and renamed, so a reader never sees half a file.
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(blob)
    os.replace(tmp, args.out)


if __name__ == "__main__":
    main()
