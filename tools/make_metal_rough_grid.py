#!/usr/bin/env python3
"""Generates scenes/metal_rough/grid.gltf: two rows of five UV spheres with glTF 2.0 metallic-roughness
materials (top row metallic 1, bottom row metallic 0; roughness 0.3 .. 0.9 left to right), geometry in
an embedded data-URI buffer. scenes/metal_rough/grid.kiln adds the camera and a point light
(written by hand). Run from the repository root: python3 tools/make_metal_rough_grid.py"""
import base64
import json
import math
import struct

ROUGHNESS = [0.3, 0.45, 0.6, 0.75, 0.9]
ROWS = [("metal", 1.0, [0.95, 0.8, 0.5], 0.55), ("dielectric", 0.0, [0.5, 0.5, 0.5], -0.55)]
RADIUS, SPACING, RINGS, SEGMENTS = 0.42, 1.0, 32, 64


def uv_sphere():
    positions, normals, indices = [], [], []
    for r in range(RINGS + 1):
        theta = math.pi * r / RINGS
        for s in range(SEGMENTS + 1):
            phi = 2 * math.pi * s / SEGMENTS
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            normals.append(n)
            positions.append(tuple(RADIUS * c for c in n))
    for r in range(RINGS):
        for s in range(SEGMENTS):
            a = r * (SEGMENTS + 1) + s
            b = a + SEGMENTS + 1
            indices += [a, a + 1, b, a + 1, b + 1, b]  # counter-clockwise seen from outside
    return positions, normals, indices


def gltf_with_sphere(generator):
    """A glTF document whose buffer holds the UV sphere (accessors 0 positions, 1 normals, 2 indices),
    with no materials, meshes or nodes yet."""
    positions, normals, indices = uv_sphere()
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    nrm = b"".join(struct.pack("<3f", *n) for n in normals)
    idx = b"".join(struct.pack("<I", i) for i in indices)
    data = pos + nrm + idx
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    gltf = {
        "asset": {"version": "2.0", "generator": generator},
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nrm), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos) + len(nrm), "byteLength": len(idx), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
        "materials": [], "meshes": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0,
    }
    return gltf


def main():
    gltf = gltf_with_sphere("kiln tools/make_metal_rough_grid.py")
    for row, metallic, base, y in ROWS:
        for i, roughness in enumerate(ROUGHNESS):
            k = len(gltf["materials"])
            gltf["materials"].append({
                "name": "%s_r%.2f" % (row, roughness),
                "pbrMetallicRoughness": {"baseColorFactor": base + [1.0], "metallicFactor": metallic,
                                         "roughnessFactor": roughness}})
            gltf["meshes"].append({"name": "sphere_%s_%d" % (row, i), "primitives": [
                {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": k}]})
            x = (i - (len(ROUGHNESS) - 1) / 2) * SPACING
            gltf["nodes"].append({"name": "sphere_%s_%d" % (row, i), "mesh": k, "translation": [x, y, 0]})
            gltf["scenes"][0]["nodes"].append(k)
    with open("scenes/metal_rough/grid.gltf", "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
