#!/usr/bin/env python3
"""kiln's subsurface and absorbing-glass materials against Cycles 3.4 on identical scenes (docs/light-
transport.md, "Against Cycles: a subsurface Lucy and absorbing glass"). A comparison, not a test.

  tools/peer/material_compare.py [--scenes lucy_sss,lucy_surface,...] [--spp 256] [--threads 2]
                                 [--out out/material_compare] [--kiln build/kiln]

Each scene is one closed mesh under the courtyard environment (the sphere: a uniform white one),
written by tools/peer_bench.py's describe() (the .kiln for kiln, the JSON tools/peer/cycles_scene.py
builds Cycles' scene from: the same camera, mesh, transform, environment lookup, 1-pixel box filter;
kiln -m N is Cycles' max_bounces N - 1);
the principled material maps to Cycles' nodes as tools/peer/cycles_principled.py says. Both renderers
render each scene twice with different seeds, SPP / 2 samples each. Printed per channel: kiln's and
Cycles' mean over the object (the pixels a kiln --transparent render covers fully) and over the whole
image, the ratio kiln / Cycles, and the noise of that ratio (the two seeds' halves disagreeing: the
standard error of the two-render mean, relative). Writes OUT/SCENE.png (kiln left, Cycles right, sRGB)
and OUT/results.md (the table, the command, the load average).
"""
import argparse
import math
import os
import re
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the checkout
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from peer_bench import describe, load_average, run_cycles, run_kiln  # noqa: E402

COURTYARD = "envmaps/courtyard.exr"
# scenes/lucy_subsurface.kiln's marble (mean free paths 4, 2.4, 1.4 cm on a 1.25 m Lucy).
MARBLE = {"base-color": [0.9, 0.8, 0.7], "roughness": 0.35, "subsurface": 1,
          "subsurface-radius": [1.0, 0.6, 0.35], "subsurface-scale": 0.04}
LUCY_VIEW = {"camera": {"position": [0.0, 0.68, 2.35], "look_at": [0.0, 0.62, 0.0], "up": [0, 1, 0],
                        "fov": 36.0},
             "environment": COURTYARD, "resolution": [150, 200], "max_depth": 16}


def lucy(material, cycles_shader=None, **view):
    """Lucy (1.25 high) in `material` (kiln attributes) under the courtyard."""
    mesh = {"mesh": "meshes/lucy.obj", "fit": ([0, 0, 0], 1.25),
            "material": {"principled": material, "cycles_shader": cycles_shader}}
    return dict(LUCY_VIEW, meshes=[mesh], **view)


SPHERE = "sphere.obj"  # written into OUT by sphere_obj()


def sphere(environment):
    """The marble on a sphere of radius 0.5 filling most of a 120 x 120 image."""
    mesh = {"mesh": SPHERE, "fit": ([0, -0.5, 0], 1.0), "material": {"principled": MARBLE}}
    return {"meshes": [mesh], "environment": environment, "resolution": [120, 120], "max_depth": 16,
            "camera": {"position": [0, 0, 3.0], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 22.0}}


SCENES = {
    # The subsurface Lucy: kiln's principled marble and Cycles' Principled BSDF with the same walk medium.
    "lucy_sss": lucy(MARBLE),
    # Its specular layer alone (base colour 0: no walk, no diffuse, no retro-reflection in Cycles).
    "lucy_surface": lucy(dict(MARBLE, **{"base-color": [0.0, 0.0, 0.0]})),
    # The same two with direct light only (kiln -m 1, Cycles 0 bounces: the walk and the light its exit
    # sees, no light from Lucy onto Lucy).
    "lucy_sss_direct": lucy(MARBLE, max_depth=1),
    "lucy_surface_direct": lucy(dict(MARBLE, **{"base-color": [0.0, 0.0, 0.0]}), max_depth=1),
    # kiln's marble against Cycles' walk alone (its Subsurface Scattering node), direct light only: with
    # lucy_sss_direct and lucy_surface_direct, Cycles' retro-reflection and exit factor in one number.
    "lucy_node_direct": lucy(MARBLE, cycles_shader="subsurface_node", max_depth=1),
    # The marble on a sphere of radius 0.5 under a uniform white environment of radiance 1 (a white
    # furnace): what the material returns of what arrives, averaged over the view angles.
    "sphere_furnace": sphere(os.path.join(ROOT, "scenes/principled_grid/white.exr")),
    # The same sphere under the courtyard: a convex object, no light from it falls on itself.
    "sphere_courtyard": sphere(COURTYARD),
    # Glass with absorption: Nefertiti (stood up) in clear principled glass (ior 1.5) whose inside absorbs,
    # the colour left after 0.5 m being 0.3 0.8 0.5 (KHR_materials_volume).
    "glass_absorb": {
        "meshes": [{"mesh": "meshes/nefertiti.obj", "fit": ([0, 0, 0], 1.0), "z_up": True,
                    "material": {"principled": {
                        "base-color": [1.0, 1.0, 1.0], "roughness": 0.0, "transmission": 1,
                        "thickness": 1, "ior": 1.5, "attenuation-color": [0.3, 0.8, 0.5],
                        "attenuation-distance": 0.5}}}],
        "camera": {"position": [0.0, 0.5, 2.3], "look_at": [0.0, 0.47, 0.0], "up": [0, 1, 0],
                   "fov": 32.0},
        "environment": COURTYARD, "resolution": [160, 200], "max_depth": 32,
    },
}
# Rows derived from two scenes' means: the walk's share of the Lucy (all light less the specular layer's;
# in Cycles that includes the retro-reflection lobe and the exit's Fresnel factor).
DIFFERENCES = {"lucy_walk": ("lucy_sss", "lucy_surface"),
               "lucy_walk_direct": ("lucy_sss_direct", "lucy_surface_direct")}
SEEDS = (11, 12)


def oiio_avg(args):
    out = subprocess.run(["oiiotool"] + args + ["--printstats"], capture_output=True, text=True,
                         check=True).stdout
    return [float(v) for v in
            re.search(r"Stats Avg: ([-0-9.eE+]+) ([-0-9.eE+]+) ([-0-9.eE+]+)", out).groups()]


def object_mask(kiln, kiln_scene, s, base):
    """1 where kiln's --transparent alpha says the mesh covers the whole pixel, else 0 (R, G, B)."""
    exr = run_kiln(kiln, kiln_scene, s, ["--transparent", "-s", "16"], 2, base + ".alpha")[2]
    mask = base + ".mask.exr"
    subprocess.run(["oiiotool", exr, "--ch", "R=A,G=A,B=A", "--subc", "0.999", "--mulc", "1e6",
                    "--clamp:min=0:max=1", "-o", mask], check=True)
    return mask


def means(exr, mask):
    """(mean RGB over the object, mean RGB over the image)."""
    covered = oiio_avg([mask])
    weighted = oiio_avg([exr, "--ch", "R,G,B", mask, "--mul"])
    return [w / c for w, c in zip(weighted, covered)], oiio_avg([exr, "--ch", "R,G,B"])


def render_pair(a, name):
    """Both renderers, both seeds: {renderer: [(object means, image means) per seed]}, and the images."""
    kiln_scene, json_path, s = describe(name, a.out, scenes=SCENES)
    base = os.path.join(a.out, name)
    mask = object_mask(a.kiln, kiln_scene, s, base)
    result, images = {"kiln": [], "cycles": []}, {"kiln": [], "cycles": []}
    for seed in SEEDS:
        k = run_kiln(a.kiln, kiln_scene, s, ["-s", str(a.spp // 2), "--seed", str(seed)], a.threads,
                     "%s.kiln.%d" % (base, seed))[2]
        c = run_cycles(a.blender, json_path, a.spp // 2, a.threads, "%s.cycles.%d.exr" % (base, seed),
                       seed)[2]
        for key, exr in (("kiln", k), ("cycles", c)):
            result[key].append(means(exr, mask))
            images[key].append(exr)
    side_by_side(images, base + ".png")
    return result


def side_by_side(images, png):
    """The two seeds' average of each renderer, kiln left, Cycles right, sRGB."""
    args = []
    for key in ("kiln", "cycles"):
        first, second = images[key]
        args += [first, "--ch", "R,G,B", second, "--ch", "R,G,B", "--add", "--mulc", "0.5"]
    subprocess.run(["oiiotool"] + args + ["--mosaic", "2x1", "--colorconvert", "linear", "sRGB",
                                          "-d", "uint8", "-o", png], check=True)


def rows(name, result):
    """Table rows: region, channel, kiln mean, Cycles mean, ratio, relative noise of the ratio."""
    out = []
    for region in (0, 1):
        for ch, label in enumerate("RGB"):
            per = {key: [seed[region][ch] for seed in result[key]] for key in result}
            mean = {key: sum(v) / 2 for key, v in per.items()}
            noise = {key: abs(v[0] - v[1]) / 2 / mean[key] for key, v in per.items()}
            out.append((name, ("object", "image")[region], label, mean["kiln"], mean["cycles"],
                        mean["kiln"] / mean["cycles"], math.hypot(noise["kiln"], noise["cycles"])))
    return out


def difference(a, b):
    """Per renderer and seed, scene a's means less scene b's."""
    return {key: [tuple([x - y for x, y in zip(ra, rb)] for ra, rb in zip(sa, sb))
                  for sa, sb in zip(a[key], b[key])] for key in a}


def sphere_obj(out):
    """A UV sphere of radius 1 with its normals (48 x 96 quads), written as OUT/sphere.obj."""
    rings, segments = 48, 96
    points = [(math.sin(math.pi * i / rings) * math.cos(2 * math.pi * j / segments),
               math.cos(math.pi * i / rings),
               -math.sin(math.pi * i / rings) * math.sin(2 * math.pi * j / segments))
              for i in range(rings + 1) for j in range(segments)]
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j + 1, (i + 1) * segments + j + 1
            c, d = (i + 1) * segments + (j + 1) % segments + 1, i * segments + (j + 1) % segments + 1
            faces += ([(a, b, d)] if i > 0 else []) + ([(b, c, d)] if i < rings - 1 else [])
    path = os.path.join(out, "sphere.obj")
    with open(path, "w") as f:
        f.writelines("v %.6f %.6f %.6f\n" % p for p in points)
        f.writelines("vn %.6f %.6f %.6f\n" % p for p in points)
        f.writelines("f %d//%d %d//%d %d//%d\n" % (a, a, b, b, c, c) for a, b, c in faces)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--spp", type=int, default=256, help="samples per pixel in all (two seeds)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "material_compare"))
    ap.add_argument("--kiln", default=os.path.join(ROOT, "build", "kiln"))
    ap.add_argument("--blender", default="blender")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    loads = ["%s at the start" % load_average()]
    table = ["| scene | region | channel | kiln | Cycles | kiln / Cycles | noise of the ratio |",
             "|---|---|---|---:|---:|---:|---:|"]
    sphere_path = sphere_obj(a.out)
    for s in SCENES.values():
        for m in s["meshes"]:
            m["mesh"] = sphere_path if m["mesh"] == SPHERE else m["mesh"]
    results = {}
    for name in a.scenes.split(","):
        results[name] = render_pair(a, name)
        loads.append("%s after %s" % (load_average(), name))
    for name, (first, second) in DIFFERENCES.items():
        if first in results and second in results:
            results[name] = difference(results[first], results[second])
    for name, result in results.items():
        for r in rows(name, result):
            table.append("| %s | %s | %s | %.4f | %.4f | %.3f | %.2g |" % r)
            print(table[-1], flush=True)
    with open(os.path.join(a.out, "results.md"), "w") as f:
        f.write("`tools/peer/material_compare.py %s`\n\n%s\n\nload average %s\n"
                % (" ".join(sys.argv[1:]), "\n".join(table), "; ".join(loads)))


if __name__ == "__main__":
    main()
