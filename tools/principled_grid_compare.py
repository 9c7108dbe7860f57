#!/usr/bin/env python3
"""The principled grid in kiln and in Cycles (docs/light-transport.md, "Against Cycles"): renders
scenes/principled_grid (tools/make_principled_grid.py) under a uniform white environment with both, and
prints each sphere's mean radiance over a square at its centre (where the view is at normal incidence,
so the value is the material's directional albedo there, plus the little its neighbours reflect) and
kiln's ratio to Cycles. A comparison, not a test.

  tools/principled_grid_compare.py KILN [--spp 128] [--threads 2] [--out DIR]
"""
import argparse
import json
import os
import re
import subprocess
import sys

GRID = "scenes/principled_grid"


def box_mean(exr, cx, cy, half):
    """Mean RGB of the (2 half) x (2 half) pixels around (cx, cy), by oiiotool."""
    x0, y0, n = int(round(cx - half)), int(round(cy - half)), int(2 * half)
    out = subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "--crop", "%dx%d+%d+%d" % (n, n, x0, y0),
                          "--printstats"], capture_output=True, text=True, check=True).stdout
    avg = re.search(r"Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)", out)
    return [float(v) for v in avg.groups()]


def system_python_env():
    """This environment without a pyenv interpreter's PATH entries and variables: Blender's embedded
    Python finds its prefix through PATH, and under pyenv loses the system's numpy (its glTF importer
    needs it)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYENV")}
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if ".pyenv" not in p)
    return env


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("kiln")
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="/tmp/principled_grid")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    desc = json.load(open(GRID + "/grid.json"))
    w, h = desc["resolution"]
    k_exr, c_exr = a.out + "/kiln.exr", a.out + "/cycles.exr"
    subprocess.run([a.kiln, "render", GRID + "/grid.kiln", "-e", GRID + "/white.exr", "-r", str(w),
                    str(h), "-s", str(a.spp),
                    # kiln -m N traces what Cycles max_bounces N - 1 does
                    "-m", str(desc["max_bounces"] + 1), "-t", str(a.threads),
                    "-q", "-o", k_exr], check=True)
    blender = subprocess.run(["blender", "-b", "--factory-startup", "--python",
                              "tools/peer/cycles_gltf.py", "--", GRID + "/grid.json", str(a.spp),
                              str(a.threads), c_exr], capture_output=True, text=True,
                             env=system_python_env())
    if not os.path.exists(c_exr):  # Blender exits 0 when the script fails
        sys.exit("Cycles wrote no image:\n" + blender.stdout[-3000:] + blender.stderr[-3000:])
    print("%-16s %8s %8s %7s" % ("sphere", "kiln", "cycles", "ratio"))
    for s in desc["spheres"]:
        half = 0.35 * s["radius_px"]
        k = box_mean(k_exr, *s["pixel"], half)[0]
        c = box_mean(c_exr, *s["pixel"], half)[0]
        print("%-16s %8.4f %8.4f %7.3f" % (s["name"], k, c, k / c if c > 0 else float("nan")))


if __name__ == "__main__":
    main()
