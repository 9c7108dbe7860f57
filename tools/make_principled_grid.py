#!/usr/bin/env python3
"""Generates scenes/principled_grid/grid.gltf and grid.json: principled spheres, base colour (grey 0.2,
0.5, 0.8) x metallic (0, 1) across, roughness (0.2, 0.5, 0.8) down, for the comparison with Cycles under
a uniform white environment (tools/principled_grid_compare.py, docs/light-transport.md). grid.json is
the camera and image both renderers use and where each sphere lands. Run from the repository root:
python3 tools/make_principled_grid.py"""
import json
import math

from make_metal_rough_grid import RADIUS, gltf_with_sphere

BASES = [0.2, 0.5, 0.8]
METALLIC = [0.0, 1.0]
ROUGHNESS = [0.2, 0.5, 0.8]
SPACING = 1.0
CAMERA = {"position": [0.0, 0.0, 14.0], "look_at": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0], "fov": 14.0}
RESOLUTION = [480, 240]


def spheres():
    """(name, base, metallic, roughness, x, y) of each sphere, columns base x metallic, rows roughness."""
    columns = [(m, b) for m in METALLIC for b in BASES]
    out = []
    for j, r in enumerate(ROUGHNESS):
        for i, (m, b) in enumerate(columns):
            x = (i - (len(columns) - 1) / 2) * SPACING
            y = ((len(ROUGHNESS) - 1) / 2 - j) * SPACING
            out.append(("b%.1f_m%.0f_r%.1f" % (b, m, r), b, m, r, x, y))
    return out


def pixel(x, y):
    """Where the camera (at z = 14 looking down -z, fov across the image's height) sees (x, y, 0)."""
    w, h = RESOLUTION
    f = (h / 2) / math.tan(math.radians(CAMERA["fov"]) / 2)
    d = CAMERA["position"][2]
    return w / 2 + x * f / d, h / 2 - y * f / d, RADIUS * f / d


def main():
    gltf = gltf_with_sphere("kiln tools/make_principled_grid.py")
    layout = []
    for k, (name, base, metallic, roughness, x, y) in enumerate(spheres()):
        gltf["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [base, base, base, 1.0], "metallicFactor": metallic,
            "roughnessFactor": roughness}})
        gltf["meshes"].append({"name": name, "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": k}]})
        gltf["nodes"].append({"name": name, "mesh": k, "translation": [x, y, 0]})
        gltf["scenes"][0]["nodes"].append(k)
        px, py, pr = pixel(x, y)
        layout.append({"name": name, "base": base, "metallic": metallic, "roughness": roughness,
                       "pixel": [px, py], "radius_px": pr})
    with open("scenes/principled_grid/grid.gltf", "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    desc = {"gltf": "scenes/principled_grid/grid.gltf", "camera": CAMERA, "resolution": RESOLUTION,
            "max_bounces": 16, "spheres": layout}
    with open("scenes/principled_grid/grid.json", "w") as f:
        json.dump(desc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
