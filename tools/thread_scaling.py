#!/usr/bin/env python3
"""Thread scaling of kiln render: each scene rendered at each thread count, interleaved (every
scene and thread count once per round, --repeats rounds), with the median of kiln's own "build Xs"
and "render Xs" figures (load and write excluded), the render's speed-up over the fewest threads
and its parallel efficiency. (The build column is not a scaling figure: Embree builds on every
core whatever -t says.) It checks that every render of a scene has the same pixels (EXR chunks
compared byte for byte; the header holds the date and thread count) and prints the load average
and the processor (a benchmark, not a test).

  tools/thread_scaling.py --kiln build/kiln --threads 1,2,4,8,16 --repeats 2 \\
      --scene "lucy=scenes/peer/lucy_env.kiln --env ../shared/envmaps/courtyard.exr -m 5 -r 300 400 -s 128"

Each scene is LABEL=ARGS (kiln render's arguments without -t and -o).
"""
import argparse
import os
import platform
import re
import shlex
import statistics
import struct
import sys
import tempfile

from bench_common import run_kiln

TIMES = re.compile(r"build ([0-9.]+)s, render ([0-9.]+)s")


def exr_pixel_bytes(path):
    """The bytes from an EXR's first chunk on: the pixels, without the header and offset table
    (whose offsets move with the header's length). Read here rather than through
    tools/images_identical.sh (idiff): the lent many-core machines this runs on have no
    OpenImageIO tools, only kiln and its carried libraries."""
    data = open(path, "rb").read()
    pos = 8  # magic number and version field
    while data[pos] != 0:  # attributes: name\0 type\0 int32 size, value
        pos = data.index(b"\0", pos) + 1
        pos = data.index(b"\0", pos) + 1
        (size,) = struct.unpack_from("<i", data, pos)
        pos += 4 + size
    (first_chunk,) = struct.unpack_from("<Q", data, pos + 1)
    return data[first_chunk:]


def render(kiln, args, threads, out):
    command = [kiln, "render"] + args + ["-t", str(threads), "-o", out]
    found = TIMES.findall(run_kiln(command))
    if not found:
        sys.exit("no 'build Xs, render Xs' in the output of: " + " ".join(command))
    return float(found[-1][0]), float(found[-1][1]), exr_pixel_bytes(out + ".exr")


def machine():
    model = "?"
    if os.path.exists("/proc/cpuinfo"):
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return "%s, %d logical processors, %s" % (model, os.cpu_count(), platform.platform())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kiln", default="build/kiln")
    ap.add_argument("--threads", default="1,2,4,8,16")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--scene", action="append", required=True, help="LABEL=ARGS")
    args = ap.parse_args()
    threads = [int(t) for t in args.threads.split(",")]
    scenes = []
    for s in args.scene:
        label, sep, rest = s.partition("=")
        if not sep or not rest.strip():
            sys.exit("--scene takes LABEL=ARGS, got " + repr(s))
        scenes.append((label, shlex.split(rest) + ["-q"]))
    print("machine: " + machine())
    print("load average at start: %.2f %.2f %.2f" % os.getloadavg(), flush=True)
    times = {(l, t): [] for l, _ in scenes for t in threads}
    pixels = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "img")
        for label, scene_args in scenes:  # warm-up: files into the page cache
            render(args.kiln, scene_args, threads[-1], out)
        for r in range(args.repeats):
            for label, scene_args in scenes:
                for t in threads:
                    build, rend, px = render(args.kiln, scene_args, t, out)
                    times[(label, t)].append((build, rend))
                    if pixels.setdefault(label, px) != px:
                        sys.exit("%s: the pixels at %d threads differ from the first render's" % (label, t))
            print("round %d done, load average %.2f" % (r + 1, os.getloadavg()[0]), flush=True)
    print("load average at end: %.2f %.2f %.2f" % os.getloadavg())
    print("%-14s %7s %9s %10s %8s %10s" %
          ("scene", "threads", "build s", "render s", "speed-up", "efficiency"))
    for label, _ in scenes:
        base = statistics.median(r for _, r in times[(label, threads[0])])
        for t in threads:
            build = statistics.median(b for b, _ in times[(label, t)])
            rend = statistics.median(r for _, r in times[(label, t)])
            speedup = base / rend
            print("%-14s %7d %9.3f %10.3f %8.2f %10.2f" %
                  (label, t, build, rend, speedup, speedup * threads[0] / t))
    print("pixels identical across thread counts: yes (every scene)")


if __name__ == "__main__":
    main()
