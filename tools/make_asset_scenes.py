#!/usr/bin/env python3
"""Writes kiln's own test scenes under scenes/assets/: small glTF 2.0 files and their textures.

Each scene is one function registered with @scene; the tests (tests/test_asset_scenes.cpp) check
pixels of these files, so a scene's layout (camera, cells, colours) is part of its contract and is
described in its docstring. Only the standard library is used (PNG written with zlib).

    tools/make_asset_scenes.py [OUT_DIR]          # default: scenes/assets beside this script
    tools/make_asset_scenes.py --only textured    # one scene

To add a scene (metal/rough grid, emissive, normal map, alpha), write a function that builds a
Gltf and returns it, decorate it with @scene("name"), and add its pixel test.
"""

import argparse
import base64
import json
import math
import os
import struct
import zlib

SCENES = {}


def scene(name):
    def register(fn):
        SCENES[name] = fn
        return fn

    return register


def write_png(path, width, height, texel):
    """An 8-bit RGB PNG; texel(x, y) gives (r, g, b) codes, row 0 at the top."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows.extend(texel(x, y))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
           chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


class Gltf:
    """A glTF 2.0 document with one embedded buffer (a data: URI) built up accessor by accessor."""

    def __init__(self):
        self.doc = {
            "asset": {"version": "2.0", "generator": "kiln tools/make_asset_scenes.py"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "buffers": [],
            "bufferViews": [],
            "accessors": [],
        }
        self.data = bytearray()
        self.files = {}  # texture file name -> writer(path)

    def _accessor(self, values, components, gl_type, fmt, target, minmax=False):
        while len(self.data) % 4:
            self.data.append(0)
        offset = len(self.data)
        flat = [v for item in values for v in (item if components > 1 else [item])]
        self.data.extend(struct.pack("<%d%s" % (len(flat), fmt), *flat))
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset,
                                        "byteLength": len(self.data) - offset, "target": target})
        kind = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}[components]
        acc = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": gl_type,
               "count": len(values), "type": kind}
        if minmax:
            acc["min"] = [min(v[i] for v in values) for i in range(components)]
            acc["max"] = [max(v[i] for v in values) for i in range(components)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def floats(self, values, components, minmax=False):
        return self._accessor(values, components, 5126, "f", 34962, minmax)

    def indices(self, values):
        return self._accessor(values, 1, 5125, "I", 34963)

    def material(self, name, **pbr):
        """pbr: glTF pbrMetallicRoughness keys (baseColorFactor, metallicFactor, ...); top-level
        material keys (emissiveFactor, alphaMode, normalTexture, ...) go in `extra`."""
        extra = pbr.pop("extra", {})
        self.doc["materials"].append(dict({"name": name, "pbrMetallicRoughness": pbr}, **extra))
        return len(self.doc["materials"]) - 1

    def texture(self, file_name, writer):
        """A texture read from file_name beside the .gltf (writer(path) writes it); its index."""
        self.files[file_name] = writer
        doc = self.doc
        doc.setdefault("images", []).append({"uri": file_name})
        doc.setdefault("samplers", [{"magFilter": 9729, "minFilter": 9987}])
        doc.setdefault("textures", []).append({"source": len(doc["images"]) - 1, "sampler": 0})
        return len(doc["textures"]) - 1

    def mesh(self, name, positions, triangles, material, uvs=None, colors=None):
        attributes = {"POSITION": self.floats(positions, 3, minmax=True),
                      "NORMAL": self.floats(flat_normals(positions, triangles), 3)}
        if uvs is not None:
            attributes["TEXCOORD_0"] = self.floats(uvs, 2)
        if colors is not None:
            attributes["COLOR_0"] = self.floats([tuple(c) + (1.0,) for c in colors], 4)
        flat = [i for t in triangles for i in t]
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": attributes, "indices": self.indices(flat), "material": material}]})
        return self.node({"name": name, "mesh": len(self.doc["meshes"]) - 1})

    def node(self, node):
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)
        return len(self.doc["nodes"]) - 1

    def camera(self, eye, yfov, aspect=1.0):
        """A perspective camera at eye looking down -Z (glTF's camera axis), +Y up."""
        self.doc.setdefault("cameras", []).append(
            {"type": "perspective",
             "perspective": {"yfov": yfov, "aspectRatio": aspect, "znear": 0.01}})
        return self.node({"name": "camera", "camera": len(self.doc["cameras"]) - 1,
                          "translation": list(eye)})

    def directional_light(self, intensity_lux, color=(1, 1, 1), rotation=(0, 0, 0, 1)):
        """KHR_lights_punctual directional light (shines down its node's -Z)."""
        ext = self.doc.setdefault("extensions", {}).setdefault("KHR_lights_punctual",
                                                               {"lights": []})
        ext["lights"].append({"type": "directional", "color": list(color),
                              "intensity": intensity_lux})
        used = self.doc.setdefault("extensionsUsed", [])
        if "KHR_lights_punctual" not in used:
            used.append("KHR_lights_punctual")
        return self.node({"name": "sun", "rotation": list(rotation),
                          "extensions": {"KHR_lights_punctual": {"light": len(ext["lights"]) - 1}}})

    def write(self, out_dir, name):
        for key in ("materials", "meshes"):
            if not self.doc[key]:
                del self.doc[key]
        self.doc["buffers"] = [{"byteLength": len(self.data),
                                "uri": "data:application/octet-stream;base64," +
                                       base64.b64encode(bytes(self.data)).decode()}]
        for file_name, writer in self.files.items():
            writer(os.path.join(out_dir, file_name))
        path = os.path.join(out_dir, name + ".gltf")
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)
            f.write("\n")
        return path


def flat_normals(positions, triangles):
    normals = [[0.0, 0.0, 0.0] for _ in positions]
    for a, b, c in triangles:
        u = [positions[b][i] - positions[a][i] for i in range(3)]
        v = [positions[c][i] - positions[a][i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        for i in (a, b, c):
            normals[i] = [normals[i][k] + n[k] for k in range(3)]
    return [[x / math.sqrt(sum(y * y for y in n)) for x in n] for n in normals]


def quad(x0, y0, x1, y1, z=0.0):
    """Corners of an axis-aligned quad facing +Z, counter-clockwise from the bottom left, with
    glTF UVs (origin at the image's top left) and its two triangles."""
    positions = [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
    uvs = [(0, 1), (1, 1), (1, 0), (0, 0)]
    return positions, uvs, [(0, 1, 2), (0, 2, 3)]


# The framing every pixel-tested scene shares: a camera at z = 2 seeing exactly x, y in [-1, 1] at
# z = 0 (yfov = 2 atan(1/2), square image), so image pixel (px, py) of an N x N render looks at
# x = -1 + 2 (px + 0.5) / N, y = 1 - 2 (py + 0.5) / N.
EYE = (0.0, 0.0, 2.0)
YFOV = 2 * math.atan(0.5)
# A directional light turned 30 degrees about -x from the view axis (a quaternion x, y, z, w): it
# shines down and into the scene, at 30 degrees from the quads' normal.
SUN = (-math.sin(math.radians(15)), 0.0, 0.0, math.cos(math.radians(15)))

# textured: colours of the checker's two cells (sRGB codes, as the PNG stores them).
CHECKER_A = (200, 50, 30)
CHECKER_B = (20, 110, 230)


@scene("textured")
def textured():
    """A quad over x, y in [-1.25, 1.25] carrying a 10 x 10 checker (16 texels a cell, 160 x 160
    PNG): the camera sees exactly its middle 8 x 8 cells, cell (0, 0) at the image's top left has
    colour CHECKER_A, and colours alternate (A where column + row is even). The image's mean
    albedo is the mean of the two cells' linear colours."""
    g = Gltf()

    def checker(path):
        write_png(path, 160, 160,
                  lambda x, y: CHECKER_A if (x // 16 + y // 16) % 2 == 0 else CHECKER_B)

    texture = g.texture("checker.png", checker)
    material = g.material("checker", baseColorTexture={"index": texture}, metallicFactor=0.0,
                          roughnessFactor=1.0)
    positions, uvs, triangles = quad(-1.25, -1.25, 1.25, 1.25)
    g.mesh("checker_quad", positions, triangles, material, uvs=uvs)
    g.camera(EYE, YFOV)
    g.directional_light(3.0, rotation=SUN)
    return g


# vertex_colored: the four quadrants' linear COLOR_0 values, listed top left, top right, bottom
# left, bottom right as seen from the camera.
QUADRANT_COLOURS = [(0.8, 0.1, 0.1), (0.1, 0.7, 0.2), (0.15, 0.2, 0.9), (0.9, 0.75, 0.1)]


@scene("vertex_colored")
def vertex_colored():
    """Four quads tiling x, y in [-1.25, 1.25], split at x = 0 and y = 0, each with one COLOR_0
    value on its four vertices (QUADRANT_COLOURS, linear as glTF defines them) and a white
    untextured material: each image quadrant's albedo is its colour."""
    g = Gltf()
    material = g.material("white", baseColorFactor=[1, 1, 1, 1], metallicFactor=0.0,
                          roughnessFactor=1.0)
    cells = [(-1.25, 0, 0, 1.25), (0, 0, 1.25, 1.25), (-1.25, -1.25, 0, 0), (0, -1.25, 1.25, 0)]
    positions, triangles, colors = [], [], []
    for (x0, y0, x1, y1), colour in zip(cells, QUADRANT_COLOURS):
        p, _, t = quad(x0, y0, x1, y1)
        triangles += [tuple(i + len(positions) for i in tri) for tri in t]
        positions += p
        colors += [colour] * 4
    g.mesh("quadrants", positions, triangles, material, colors=colors)
    g.camera(EYE, YFOV)
    g.directional_light(3.0, rotation=SUN)
    return g


# metal_rough_texture: the metallicRoughnessTexture's two halves as (metallic, roughness) 8-bit
# codes (glTF: B metallic, G roughness), the left half first.
MR_LEFT = (255, 128)  # metal, roughness 128/255
MR_RIGHT = (0, 204)   # dielectric, roughness 204/255
MR_BASE = (0.9, 0.6, 0.2)


@scene("metal_rough_texture")
def metal_rough_texture():
    """The textured quad's layout (x, y in [-1.25, 1.25], sun at 30 degrees) with a principled
    material of base colour MR_BASE, metallicFactor and roughnessFactor 1, and a 64 x 64
    metallicRoughnessTexture whose left half (image x < 0: pixel columns 0..31 of a 64 x 64
    render) holds MR_LEFT and right half MR_RIGHT: each half shades as the constant material with
    those factors."""
    g = Gltf()

    def halves(path):
        write_png(path, 64, 64, lambda x, y: (0, (MR_LEFT if x < 32 else MR_RIGHT)[1],
                                              (MR_LEFT if x < 32 else MR_RIGHT)[0]))

    texture = g.texture("metal_rough_halves.png", halves)
    material = g.material("metal_rough", baseColorFactor=list(MR_BASE) + [1],
                          metallicFactor=1.0, roughnessFactor=1.0,
                          metallicRoughnessTexture={"index": texture})
    positions, uvs, triangles = quad(-1.25, -1.25, 1.25, 1.25)
    g.mesh("metal_rough_quad", positions, triangles, material, uvs=uvs)
    g.camera(EYE, YFOV)
    g.directional_light(3.0, rotation=SUN)
    return g


# emissive: the panel's emissive texture codes (sRGB, grey) in its top and bottom halves, its
# emissiveFactor and KHR_materials_emissive_strength.
EMISSIVE_TOP = 255
EMISSIVE_BOTTOM = 128
EMISSIVE_STRENGTH = 4.0


@scene("emissive")
def emissive():
    """A white floor (x, y in [-1.25, 1.25], z = 0) lit only by an emitting panel above its right
    side: x in [0.2, 1.25], y in [-1.25, 1.25], z = 0.5, facing the camera (and, emitters being
    two-sided, the floor). The panel's base colour is black (it reflects next to nothing); its
    64 x 64 emissive texture is EMISSIVE_TOP in its upper half (y > 0) and EMISSIVE_BOTTOM in its
    lower half, times emissiveFactor 1 and KHR_materials_emissive_strength EMISSIVE_STRENGTH. Seen
    from the camera (1.5 units away, 0.75 units a half image) the panel covers pixel columns 41..63
    of a 64 x 64 render, its halves split at row 32; the floor fills columns 0..39."""
    g = Gltf()

    def halves(path):
        write_png(path, 64, 64, lambda x, y: (EMISSIVE_TOP if y < 32 else EMISSIVE_BOTTOM,) * 3)

    texture = g.texture("emissive_halves.png", halves)
    floor = g.material("floor", baseColorFactor=[0.8, 0.8, 0.8, 1], metallicFactor=0.0,
                       roughnessFactor=1.0)
    panel = g.material("panel", baseColorFactor=[0, 0, 0, 1], metallicFactor=0.0,
                       roughnessFactor=1.0,
                       extra={"emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": texture},
                              "extensions": {"KHR_materials_emissive_strength":
                                             {"emissiveStrength": EMISSIVE_STRENGTH}}})
    g.doc.setdefault("extensionsUsed", []).append("KHR_materials_emissive_strength")
    positions, uvs, triangles = quad(-1.25, -1.25, 1.25, 1.25)
    g.mesh("floor", positions, triangles, floor, uvs=uvs)
    positions, uvs, triangles = quad(0.2, -1.25, 1.25, 1.25, z=0.5)
    g.mesh("panel", positions, triangles, panel, uvs=uvs)
    g.camera(EYE, YFOV)
    return g


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", nargs="?",
                        default=os.path.normpath(os.path.join(here, "..", "scenes", "assets")))
    parser.add_argument("--only", choices=sorted(SCENES), action="append")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    for name in args.only or sorted(SCENES):
        print(SCENES[name]().write(args.out_dir, name))


if __name__ == "__main__":
    main()
