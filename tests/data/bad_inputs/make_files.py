#!/usr/bin/env python3
"""Writes the binary files of the bad-input corpus (cases.txt) from code, so
each is reproducible: model files whose metadata lies (their checksum made
right, so the reader gets past it), headers that claim far more data than
the file holds, and a map with negative pixels.
Run from anywhere: tests/data/bad_inputs/make_files.py"""

import pathlib
import struct

HERE = pathlib.Path(__file__).resolve().parent
SEED_MODEL = HERE.parent.parent / "fuzz" / "corpus" / "model_file" / "supplement.nuldnet"


def fnv1a(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def model_with(**changes):
    """The seed model with metadata keys replaced, checksum rewritten."""
    raw = SEED_MODEL.read_bytes()
    assert raw[:8] == b"NULDNET1"
    (meta_bytes,) = struct.unpack_from("<I", raw, 8)
    meta = dict(line.split("=", 1) for line in raw[12:12 + meta_bytes].decode().splitlines())
    meta.update({k: str(v) for k, v in changes.items()})
    text = "".join(f"{k}={v}\n" for k, v in sorted(meta.items())).encode()
    body = b"NULDNET1" + struct.pack("<I", len(text)) + text + raw[12 + meta_bytes:-8]
    return body + struct.pack("<Q", fnv1a(body))


def main():
    (HERE / "model_huge_network.nuldnet").write_bytes(model_with(hidden=16384, n=4096))
    (HERE / "model_negative_seed.nuldnet").write_bytes(model_with(seed=-1))
    (HERE / "model_fractional_n.nuldnet").write_bytes(model_with(n=8.5))
    (HERE / "huge_header.pfm").write_bytes(b"PF\n1000000 1000000\n-1.0\n" + bytes(64))
    # A binary point set whose header claims 2^40 points.
    (HERE / "huge_header.ptsb").write_bytes(
        b"NULDPTS1" + struct.pack("<IQQI", 2, 1 << 40, 1, 0) + bytes(32))
    (HERE / "huge_count.ply").write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
        b"property float x\nproperty float y\nproperty float z\nelement face 1\n"
        b"property list uchar int vertex_indices\nend_header\n" + bytes(64))
    # An 8 x 4 map (PFM: little-endian floats, bottom row first) with three
    # negative values in one pixel and one in another.
    pixels = [0.5] * 96
    pixels[0:3] = [-0.25, -0.5, -0.25]
    pixels[40] = -2.0
    (HERE / "negative_map.pfm").write_bytes(b"PF\n8 4\n-1.0\n" + struct.pack("<96f", *pixels))

    # Random bytes (fixed seed) given as text and binary point sets and as a
    # model: readers must say what is wrong without echoing them.
    import random
    noise = random.Random(7).randbytes(300)
    (HERE / "random_bytes.txt").write_bytes(noise)
    (HERE / "random_bytes.ptsb").write_bytes(noise)
    (HERE / "random_after_magic.ptsb").write_bytes(b"NULDPTS1" + noise)
    (HERE / "random_bytes.nuldnet").write_bytes(noise)
    # A glTF binary header followed by noise, and one triangle whose
    # material's roughness is out of range.
    (HERE / "random_after_magic.glb").write_bytes(
        b"glTF" + struct.pack("<II", 2, 12 + len(noise)) + noise)
    import base64
    import json
    blob = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    (HERE / "bad_roughness.gltf").write_text(json.dumps({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(blob)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "materials": [{"name": "shiny", "pbrMetallicRoughness": {"roughnessFactor": 1.5}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}, indent=1) + "\n")

if __name__ == "__main__":
    main()
