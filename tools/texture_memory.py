#!/usr/bin/env python3
"""Renders a scene with more texture data than kiln's texture cache and reports peak memory.

Writes COUNT half-float EXR textures of SIZE x SIZE RGB, tiled and MIP-mapped as maketx writes them
(default 22 x 4096^2: 2.06 GiB of texels at level 0, 2.75 GiB with the MIP levels), with oiiotool
into a scratch directory, an OBJ of COUNT quads each with its own texture, and the same OBJ
untextured. --untiled writes plain scanline float EXRs instead, which kiln converts into tiled MIP
files in its texture cache directory at load (set KILN_TEXTURE_CACHE to choose it; a second run
reuses them). Renders both with
`kiln render --json --texture-cache-mb MB` and prints each peak resident memory (getrusage of the
kiln process) and the textured peak minus the untextured one, which the cache bounds.

    tools/texture_memory.py build/kiln [--count 22] [--size 4096] [--cache-mb 64] [--untiled]
                            [--image 2048] [--dir DIR]

tests/test_texture_memory.cpp runs the same check on 240 MiB of tiled textures.
"""

import argparse
import json
import math
import os
import subprocess
import tempfile


def texture_name(i, untiled):
    return "tex%d%s.exr" % (i, "_scanline" if untiled else "")


def write_textures(directory, count, size, untiled):
    for i in range(count):
        path = os.path.join(directory, texture_name(i, untiled))
        if os.path.exists(path):
            continue
        # A gradient with a per-texture tint: every texel differs, nothing is constant.
        corners = "topleft=%g,0,1:topright=1,%g,0:bottomleft=0,1,%g:bottomright=1,1,1" % (
            i / count, i / count, i / count)
        form = ["-d", "float", "--compression", "none", "-o", path] if untiled else \
            ["-d", "half", "--compression", "none", "-otex:hash=0", path]
        subprocess.run(["oiiotool", "--pattern", "fill:" + corners, "%dx%d" % (size, size), "3"]
                       + form, check=True)


def write_scene(directory, name, count, textured, untiled=False):
    mtl, obj = [], ["mtllib %s.mtl" % name, "vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1"]
    for i in range(count):
        mtl += ["newmtl m%d" % i, "Kd 1 1 1"] + (["map_Kd " + texture_name(i, untiled)] if textured else [])
        cols = math.ceil(math.sqrt(count))  # a square grid: the image covers every quad
        x0, y0 = (i % cols) * 1.1, (i // cols) * 1.1
        obj += ["usemtl m%d" % i] + ["v %g %g 0" % p for p in
                                     [(x0, y0), (x0 + 1, y0), (x0 + 1, y0 + 1), (x0, y0 + 1)]]
        v = 4 * i + 1
        obj += ["f %d/1 %d/2 %d/3" % (v, v + 1, v + 2), "f %d/1 %d/3 %d/4" % (v, v + 2, v + 3)]
    with open(os.path.join(directory, name + ".mtl"), "w") as f:
        f.write("\n".join(mtl) + "\n")
    path = os.path.join(directory, name + ".obj")
    with open(path, "w") as f:
        f.write("\n".join(obj) + "\n")
    return path


def render(kiln, scene, directory, cache_mb, side):
    # Beauty only, 1 spp: the film stays small while side^2 pixels look up fine MIP levels (a
    # 2048^2 image reads well over 64 MiB of texels from 22 textures).
    out = subprocess.run([kiln, "render", scene, "-o", os.path.join(directory, "out.exr"),
                          "-r", str(side), str(side), "-s", "1", "-q", "--json", "--aov", "none",
                          "--texture-cache-mb", str(cache_mb)],
                         check=True, capture_output=True, text=True)
    result = json.loads(out.stdout)
    return result["peak_memory_bytes"] / 2**20, sum(result["seconds"].values())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kiln")
    parser.add_argument("--count", type=int, default=22)
    parser.add_argument("--size", type=int, default=4096)
    parser.add_argument("--cache-mb", type=int, default=64)
    parser.add_argument("--image", type=int, default=2048, help="square image side in pixels")
    parser.add_argument("--untiled", action="store_true")
    parser.add_argument("--dir", help="scratch directory (kept; default: a new temporary one)")
    args = parser.parse_args()
    directory = args.dir or tempfile.mkdtemp(prefix="kiln-texture-memory-")
    os.makedirs(directory, exist_ok=True)
    write_textures(directory, args.count, args.size, args.untiled)
    texels = args.count * args.size * args.size * 3 * (4 if args.untiled else 2) / 2**20
    width = args.image
    plain, plain_s = render(args.kiln, write_scene(directory, "plain", args.count, False),
                            directory, args.cache_mb, width)
    textured, textured_s = render(args.kiln, write_scene(directory, "textured", args.count, True, args.untiled),
                                  directory, args.cache_mb, width)
    print("textures:        %d x %d^2 RGB %s = %.0f MiB at level 0 (%s)" % (
        args.count, args.size, "float scanline" if args.untiled else "half tiled MIP-mapped",
        texels, directory))
    print("cache limit:     %d MiB" % args.cache_mb)
    print("untextured peak: %.0f MiB (%.1f s)" % (plain, plain_s))
    print("textured peak:   %.0f MiB (%.1f s)" % (textured, textured_s))
    print("difference:      %.0f MiB = cache + %.0f MiB" % (textured - plain,
                                                             textured - plain - args.cache_mb))


if __name__ == "__main__":
    main()
