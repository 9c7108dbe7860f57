#!/usr/bin/env python3
"""Writes the normal-map, alpha and texture-transform test scenes under scenes/assets/ (small glTF
files with their geometry as data URIs, PNG textures written here with zlib alone, one float EXR
through oiiotool) and the .kiln scenes that light and frame them. Run from the repository root:
    python3 tools/make_maps_scenes.py
The tests (tests/test_maps.cpp) read the files it writes; the files are committed."""
import base64
import json
import math
import os
import struct
import subprocess
import zlib

OUT = os.path.join("scenes", "assets")


def png(path, width, height, channels, texel):
    """8-bit PNG (grey, RGB or RGBA): texel(x, y) -> tuple of floats in [0, 1], y down."""
    colour_type = {1: 0, 3: 2, 4: 6}[channels]
    rows = b""
    for y in range(height):
        row = bytearray([0])
        for x in range(width):
            row += bytes(max(0, min(255, round(c * 255))) for c in texel(x, y))
        rows += bytes(row)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def quad(y, x0, x1, z0, z1, normal_up=True):
    """Positions, normals, UVs (glTF: u along +x, v along +z, v = 0 at z0), tangents, indices."""
    pos = [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    idx = [0, 2, 1, 0, 3, 2] if normal_up else [0, 1, 2, 0, 2, 3]
    return pos, uv, idx


def gltf(path, quads, materials, images, with_tangents=False):
    """quads: list of (quad(), material index). materials: glTF material dicts (textures by image
    index). Geometry goes into one data-URI buffer."""
    blob = b""
    views, accessors, meshes, nodes = [], [], [], []

    def add(data, fmt, count, kind, target, minmax=None):
        nonlocal blob
        while len(blob) % 4:
            blob += b"\0"
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data),
                      "target": target})
        blob += data
        acc = {"bufferView": len(views) - 1, "componentType": fmt, "count": count, "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        accessors.append(acc)
        return len(accessors) - 1

    for (pos, uv, idx), mat in quads:
        flat = [c for p in pos for c in p]
        lo = [min(p[i] for p in pos) for i in range(3)]
        hi = [max(p[i] for p in pos) for i in range(3)]
        attrs = {
            "POSITION": add(struct.pack("<%df" % len(flat), *flat), 5126, 4, "VEC3", 34962,
                            (lo, hi)),
            "NORMAL": add(struct.pack("<12f", *([0, 1, 0] * 4)), 5126, 4, "VEC3", 34962),
            "TEXCOORD_0": add(struct.pack("<8f", *[c for t in uv for c in t]), 5126, 4, "VEC2",
                              34962),
        }
        if with_tangents:
            attrs["TANGENT"] = add(struct.pack("<16f", *([1, 0, 0, 1] * 4)), 5126, 4, "VEC4",
                                   34962)
        ind = add(struct.pack("<6H", *idx), 5123, 6, "SCALAR", 34963)
        meshes.append({"primitives": [{"attributes": attrs, "indices": ind, "material": mat}]})
        nodes.append({"mesh": len(meshes) - 1})
    doc = {
        "asset": {"version": "2.0", "generator": "kiln tools/make_maps_scenes.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    if images:
        doc["images"] = [{"uri": name} for name in images]
        doc["textures"] = [{"source": i} for i in range(len(images))]
        doc["samplers"] = [{}]
    if any("KHR_texture_transform" in json.dumps(m) for m in materials):
        doc["extensionsUsed"] = ["KHR_texture_transform"]
    with open(os.path.join(OUT, path), "w") as f:
        json.dump(doc, f, indent=1)


# glTF materials import as kiln's principled material; the tests' expected pixels are Lambert's
# (albedo E cos / pi), so the wrappers render the assets diffuse (base colour, textures and maps kept).
def kiln(path, include, light_dir, camera, extra=""):
    with open(os.path.join(OUT, path), "w") as f:
        f.write('<kiln-scene>\n  <include file="%s">\n    <override spec="diffuse"/>\n  </include>\n%s'
                '  <light kind="directional" radiance="3 3 3" direction="%s"/>\n'
                '  <camera position="0 4 0" look-at="0 0 0" up="0 0 -1" fov="%s"/>\n'
                '</kiln-scene>\n' % (include, extra, light_dir, camera))


def textures():
    # Normal map: left half of the image tilted towards +x (tangent), right half towards -x; tilt
    # 45 degrees, so a light from straight above falls at cos 45 instead of 1.
    t = math.sqrt(0.5)
    png(os.path.join(OUT, "maps_tilted_normals.png"), 16, 16, 3,
        lambda x, y: (0.5 + 0.5 * (t if x < 8 else -t), 0.5, 0.5 + 0.5 * t))
    # Every texel tilted 45 degrees towards +y (the bitangent: increasing v, up the image).
    png(os.path.join(OUT, "maps_tilted_up.png"), 4, 4, 3, lambda x, y: (0.5, 0.5 + 0.5 * t, 0.5 + 0.5 * t))
    # A flat map stored exactly: (0.5, 0.5, 1) in half floats.
    subprocess.run(["oiiotool", "--nosoftwareattrib", "--pattern", "constant:color=0.5,0.5,1", "8x8", "3", "-d", "half",
                    "-o", os.path.join(OUT, "maps_flat_normals.exr")], check=True)
    # Card: red, alpha 0 on the image's top half (v < 0.5: the -z half of the card), 1 below.
    png(os.path.join(OUT, "maps_card_rgba.png"), 16, 16, 4,
        lambda x, y: (1.0, 0.1, 0.1, 0.0 if y < 8 else 1.0))
    # Texture transform: left half black, right half white; scaled by 0.5 it shows the left half only.
    png(os.path.join(OUT, "maps_half_white.png"), 16, 16, 3,
        lambda x, y: (0, 0, 0) if x < 8 else (1, 1, 1))


def main():
    os.makedirs(OUT, exist_ok=True)
    textures()
    floor = quad(0.0, -1, 1, -1, 1)
    white = {"name": "white",
             "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}}
    normal_mapped = dict(white, name="normal_mapped", normalTexture={"index": 0})
    flat_mapped = dict(white, name="flat_mapped", normalTexture={"index": 0})
    gltf("maps_normal_none.gltf", [(floor, 0)], [white], [])
    gltf("maps_normal.gltf", [(floor, 0)], [normal_mapped], ["maps_tilted_normals.png"])
    gltf("maps_normal_tangents.gltf", [(floor, 0)], [normal_mapped], ["maps_tilted_normals.png"],
         with_tangents=True)
    gltf("maps_normal_flat.gltf", [(floor, 0)], [flat_mapped], ["maps_flat_normals.exr"])
    # Side light (travelling towards +x, from the -x side) shows the tangent's sign; light from the
    # -z side (where glTF v = 0, the image's top) the bitangent's.
    kiln("maps_normal_side.kiln", "maps_normal.gltf", "1 -1 0", "60")
    up_mapped = dict(white, name="tilted_up", normalTexture={"index": 0})
    gltf("maps_normal_up.gltf", [(floor, 0)], [up_mapped], ["maps_tilted_up.png"])
    kiln("maps_normal_up.kiln", "maps_normal_up.gltf", "0 -1 1", "60")
    half_strength = dict(white, name="half_strength", normalTexture={"index": 0, "scale": 0.5})
    gltf("maps_normal_scale.gltf", [(floor, 0)], [half_strength], ["maps_tilted_normals.png"])
    kiln("maps_normal_scale.kiln", "maps_normal_scale.gltf", "0 -1 0", "60")
    # Light from straight above; the normal map's tilt is about the tangent (+x).
    for name in ("none", "", "_tangents", "_flat"):
        suffix = "_" + name if name not in ("", "_tangents", "_flat") else name
        kiln("maps_normal%s.kiln" % suffix, "maps_normal%s.gltf" % suffix, "0 -1 0", "60")

    # Alpha: a green floor under the left half (x < 0) at y = 0, a card at y = 0.5 over all of it.
    green = {"name": "floor",
             "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.7, 0.2, 1], "metallicFactor": 0}}
    card = {"name": "card", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
            "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                     "baseColorTexture": {"index": 0}}}
    blend = {"name": "veil", "alphaMode": "BLEND", "doubleSided": True,
             "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 0.3],
                                      "metallicFactor": 0}}
    left_floor = quad(0.0, -1, 0, -1, 1)
    card_quad = quad(0.5, -1, 1, -1, 1)
    gltf("maps_alpha_mask.gltf", [(left_floor, 0), (card_quad, 1)], [green, card],
         ["maps_card_rgba.png"])
    gltf("maps_alpha_blend.gltf", [(left_floor, 0), (card_quad, 1)], [green, blend], [])
    kiln("maps_alpha_mask.kiln", "maps_alpha_mask.gltf", "0 -1 0", "60")
    kiln("maps_alpha_blend.kiln", "maps_alpha_blend.gltf", "0 -1 0", "60")

    # KHR_texture_transform: scale 0.5 shows the texture's left (black) half over the whole quad;
    # offset 0.5 with it shows the right (white) half.
    def transformed(name, ext):
        return {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": ext}}}}
    gltf("maps_transform_scale.gltf", [(floor, 0)],
         [transformed("scaled", {"scale": [0.5, 1]})], ["maps_half_white.png"])
    gltf("maps_transform_offset.gltf", [(floor, 0)],
         [transformed("offset", {"scale": [0.5, 1], "offset": [0.5, 0]})],
         ["maps_half_white.png"])
    gltf("maps_transform_rotate.gltf", [(floor, 0)],
         [transformed("rotated", {"rotation": math.pi / 2})], ["maps_half_white.png"])
    for name in ("scale", "offset", "rotate"):
        kiln("maps_transform_%s.kiln" % name, "maps_transform_%s.gltf" % name, "0 -1 0", "60")


if __name__ == "__main__":
    main()
