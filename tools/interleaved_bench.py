#!/usr/bin/env python3
"""Interleaved render timing: runs each variant's kiln command in turn (A B A B ...), --repeats rounds,
and prints the median and the fastest render time of each (kiln's own "render Xs" figure: load,
build and write excluded) and their ratios to the first variant's, all from the same run (a benchmark, not a test).

  tools/interleaved_bench.py --repeats 7 \\
      --variant "base=/tmp/kiln_old render scene.kiln -s 64 -q -o /tmp/a" \\
      --variant "new=build/kiln render scene.kiln -s 64 -q -o /tmp/b"

Each variant is LABEL=COMMAND (split like a shell line, no shell features); a kiln binary copied
elsewhere needs its kiln_image.so (the image module) copied beside it. One warm-up round is run
and discarded so every variant starts with the files in the page cache.
"""
import argparse
import re
import shlex
import statistics
import sys

from bench_common import run_kiln

RENDER_TIME = re.compile(r"render ([0-9.]+)s")


def render_seconds(command):
    found = RENDER_TIME.findall(run_kiln(command))
    if not found:
        sys.exit("no 'render Xs' in the output of: " + " ".join(command))
    return float(found[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variant", action="append", required=True, help="LABEL=COMMAND")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    variants = []
    for v in args.variant:
        label, sep, command = v.partition("=")
        if not sep or not command.strip():
            sys.exit("--variant takes LABEL=COMMAND, got " + repr(v))
        variants.append((label, shlex.split(command)))
    for _, command in variants:  # warm-up
        render_seconds(command)
    times = {label: [] for label, _ in variants}
    for r in range(args.repeats):
        for label, command in variants:
            times[label].append(render_seconds(command))
        print("round %d: %s" % (r + 1, "  ".join("%s %.3fs" % (l, times[l][-1]) for l, _ in variants)),
              flush=True)
    # The minimum too: on a shared machine whose speed drifts between runs, each variant's fastest
    # run is the one least slowed by its neighbours.
    base = statistics.median(times[variants[0][0]])
    base_min = min(times[variants[0][0]])
    print("%-14s %10s %8s %10s %8s" % ("variant", "median s", "ratio", "min s", "ratio"))
    for label, _ in variants:
        m, lo = statistics.median(times[label]), min(times[label])
        print("%-14s %10.3f %8.3f %10.3f %8.3f" % (label, m, m / base, lo, lo / base_min))


if __name__ == "__main__":
    main()
