#!/usr/bin/env python3
"""Writes the fuzz harnesses' seed corpora and the assets the scene seeds name
(tests/fuzz/README.md). Small valid files of every kind each reader accepts;
the fuzzer mutates from there. Run from anywhere; needs oiiotool for the
environment map and, for the model seeds, a built nuld:

    tests/fuzz/make_corpus.py [--nuld build/tools/nuld/nuld]

Findings kept in the corpora (files named finding-*) are left alone."""

import argparse
import base64
import json
import pathlib
import shutil
import struct
import subprocess
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
CORPUS = HERE / "corpus"
ASSETS = HERE / "assets"

TETRA = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(path, data):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data if isinstance(data, bytes) else data.encode())


def ply_ascii():
    lines = ["ply", "format ascii 1.0", "comment a tetrahedron and a quad",
             "element vertex 5", "property float x", "property float y", "property float z",
             "property float nx", "property float ny", "property float nz",
             "element face 5", "property list uchar int vertex_indices", "end_header"]
    lines += [f"{x} {y} {z} 0 0 1" for x, y, z in TETRA + [(1, 1, 0)]]
    lines += ["3 " + " ".join(map(str, f)) for f in TETRA_FACES]
    lines += ["4 0 1 4 2"]
    return "\n".join(lines) + "\n"


def ply_binary(big_endian):
    order = ">" if big_endian else "<"
    name = "binary_big_endian" if big_endian else "binary_little_endian"
    coord = "double" if big_endian else "float"
    index = "vertex_index" if big_endian else "vertex_indices"
    header = "\n".join([
        "ply", f"format {name} 1.0", "element vertex 4", f"property {coord} x",
        f"property {coord} y", f"property {coord} z", "property uchar red",
        "element face 4", f"property list uchar uint {index}",
        "element edge 1", "property list uchar int vertex_pair", "end_header"]) + "\n"
    body = b""
    for v in TETRA:
        body += struct.pack(order + ("3d" if big_endian else "3f"), *v) + bytes([200])
    for f in TETRA_FACES:
        body += struct.pack(order + "B3I", 3, *f)
    body += struct.pack(order + "B2i", 2, 0, 1)
    return header.encode() + body


def gltf_triangle():
    """A triangle with normals and ushort indices under a translated, scaled node."""
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    normals = struct.pack("<9f", *([0, 0, 1] * 3))
    indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    buffer = positions + normals + indices
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "tri", "translation": [0, 1, 0], "scale": [2, 2, 2],
                   "children": [1]},
                  {"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 3, 1]}],
        "meshes": [{"name": "triangle", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "tri_material"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
        "buffers": [{"byteLength": len(buffer)}],
    }
    return doc, buffer


def gltf_text():
    doc, buffer = gltf_triangle()
    doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64," +
                                base64.b64encode(buffer).decode())
    return json.dumps(doc, indent=1)


def glb():
    doc, buffer = gltf_triangle()
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    buffer += b"\0" * (-len(buffer) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text
    chunks += struct.pack("<I4s", len(buffer), b"BIN\0") + buffer
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


SETS = [[(0.125, 0.375), (0.625, 0.875), (0.375, 0.125), (0.875, 0.625)],
        [(0.25, 0.25), (0.75, 0.75), (0.25, 0.75), (0.75, 0.25)]]


def pointset_text():
    out = "# format: 1\n# n: 4\n# instances: 2\n# target: gaussian:0.5,0.5,0.1\n"
    for k, s in enumerate(SETS):
        out += f"# set {k}\n" + "".join(f"{x} {y}\n" for x, y in s)
    return out


def pointset_utk():
    return "".join("#\n" + "".join(f"{x:.17g}\t{y:.17g}\n" for x, y in s) for s in SETS)


def pointset_binary_body(meta):
    """What follows the magic (the binary harness puts the magic in front)."""
    meta = meta.encode()
    body = struct.pack("<IQQI", 2, 4, 2, len(meta)) + meta
    for s in SETS:
        for p in s:
            body += struct.pack("<2d", *p)
    return body


DISNEY = {"type": "disney", "base_color": [0.8, 0.5, 0.3], "metallic": 0.5, "roughness": 0.3,
          "specular": 0.5, "clearcoat": 0.2, "sheen": 0.1, "anisotropic": 0.4}
CAMERA = {"eye": [0, 2, 6], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov": 40}


def scenes():
    yield "shapes.json", {
        "camera": CAMERA, "film": {"width": 32, "height": 24},
        "render": {"spp": 4, "integrator": "path", "max_depth": 3, "backend": "sobol", "seed": 1},
        "materials": {"default": {"type": "lambertian", "albedo": 0.5}, "shiny": DISNEY},
        "meshes": [{"shape": "floor", "half_size": 5, "height": 0},
                   {"shape": "sphere", "center": [0, 1, 0], "radius": 1, "material": "shiny"}]}
    yield "files.json", {
        "camera": dict(CAMERA, mirror_x=True),
        "environment": {"file": "map.exr", "scale": 2, "rotation": 90, "up": [0, 1, 0],
                        "importance": "mean"},
        "materials": {"mesh": {"type": "lambertian", "albedo": [0.2, 0.4, 0.6]},
                      "tri_material": DISNEY},
        "meshes": [{"file": "mesh.ply", "transform": {"scale": 2, "rotate_y": 30,
                                                       "translate": [0, 1, 0]}},
                   {"file": "mesh.gltf", "skip": ["triangle"]},
                   {"file": "mesh.gltf", "material": "mesh"}]}
    yield "upside_down.json", {
        "camera": CAMERA, "environment": {"file": "map.exr", "up": [0, -1, 0]},
        "materials": {"default": {"type": "disney", "roughness": 0}},
        "meshes": [{"shape": "sphere"}], "comment": "a map stored upside down"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nuld", help="a built nuld, to write the model seeds")
    args = parser.parse_args()

    write(ASSETS / "mesh.ply", ply_ascii())
    write(ASSETS / "mesh.gltf", gltf_text())
    subprocess.run(["oiiotool", "--pattern", "fill:top=1,0.9,0.8:bottom=0.1,0.1,0.2", "8x4", "3",
                    "-d", "half", "-o", str(ASSETS / "map.exr")], check=True)

    write(CORPUS / "ply" / "ascii.ply", ply_ascii())
    write(CORPUS / "ply" / "little_endian.ply", ply_binary(False))
    write(CORPUS / "ply" / "big_endian.ply", ply_binary(True))
    write(CORPUS / "gltf" / "triangle.gltf", gltf_text())
    write(CORPUS / "gltf" / "triangle.glb", glb())
    write(CORPUS / "pointset_text" / "nuld.txt", pointset_text())
    write(CORPUS / "pointset_text" / "utk.txt", pointset_utk())
    write(CORPUS / "pointset_binary" / "with_metadata",
          pointset_binary_body("target=gaussian:0.5,0.5,0.1\nseed=3\n"))
    write(CORPUS / "pointset_binary" / "bare", pointset_binary_body(""))
    for name, scene in scenes():
        write(CORPUS / "scene_json" / name, json.dumps(scene, indent=1))

    if args.nuld:
        with tempfile.TemporaryDirectory() as tmp:
            tiny = ["--n", "8", "--hidden", "8", "--steps", "2", "--batch", "2", "--boxes", "32",
                    "-q"]
            runs = {"supplement.nuldnet": ["--target", "family:gaussian"],
                    "graph.nuldnet": ["--target", "family:disney", "--arch", "graph",
                                      "--stages", "2"]}
            for name, extra in runs.items():
                out = pathlib.Path(tmp) / name
                subprocess.run([args.nuld, "train", *extra, *tiny, "-o", str(out)], check=True)
                write(CORPUS / "model_file" / name, out.read_bytes())


if __name__ == "__main__":
    main()
