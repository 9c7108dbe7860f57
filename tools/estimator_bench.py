#!/usr/bin/env python3
"""Time to equal error within kiln: which estimator settings (sampler, light samples, Russian roulette,
adaptive sampling) reach a given relative MSE soonest on a scene (a benchmark, not a test).

  tools/estimator_bench.py --scene "SCENE.kiln --env MAP.exr -r 320 240 -t 2" \\
      --ref "--sampler sobol -s 1024" --spp 16,64,256 --repeats 3 \\
      --variant "independent=--sampler independent" --variant "sobol=--sampler sobol" \\
      --variant "noise=--sampler sobol -s 1024 --noise-threshold {p}@0.2,0.1,0.05"

A variant is LABEL=[KILN::]ARGS[@P1,P2,...]: its renders are SCENE ARGS (by the binary KILN, default
--kiln, e.g. an older build to compare against) with {p} replaced by each point (default points: --spp, with "-s {p}" added when ARGS has no {p}). All renders of a round run
interleaved (every variant at every point), --repeats rounds; times are medians of kiln's
"build + render" seconds (load and write excluded). Error: `kiln bench compare TEST REF`, the
luminance relMSE against the reference rendered once with SCENE REF (its variance channel removes its
own noise). Error levels: the first variant's errors at its middle and last points; each variant's
time to reach a level is interpolated log-log along its own (time, error) series ('*' marks an
extrapolation). The ratio is variant time / first variant time: below 1 is faster to that error.
"""
import argparse
import os
import re
import shlex
import statistics
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the checkout
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import parse_variant, time_at  # noqa: E402  (shared with tools/peer_bench.py)

TIMES = re.compile(r"build ([0-9.]+)s, render ([0-9.]+)s")


def render(kiln, scene_args, args, out_base):
    cmd = [kiln, "render"] + scene_args + args + ["-q", "-o", out_base]
    run = subprocess.run(cmd, capture_output=True, text=True)
    m = TIMES.search(run.stderr)
    if run.returncode != 0 or not m:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), run.stderr[-2000:]))
    return float(m.group(1)) + float(m.group(2))


def rel_mse(kiln, test, ref):
    out = subprocess.run([kiln, "bench", "compare", test, ref], capture_output=True, text=True,
                         check=True).stdout
    return float(re.search(r"relmse ([0-9.eE+-]+)", out).group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kiln", default=os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "build", "kiln"))
    ap.add_argument("--scene", required=True, help="scene file and the options every render shares")
    ap.add_argument("--ref", required=True, help="the reference's options (e.g. -s 2048)")
    ap.add_argument("--spp", default="16,64,256")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--variant", action="append", required=True)
    ap.add_argument("--out", default="out/estimators")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scene = shlex.split(a.scene)
    variants = [parse_variant(v, a.spp.split(","), a.kiln) for v in a.variant]
    ref = os.path.join(a.out, "reference")
    if not os.path.exists(ref + ".exr"):
        print("reference: %.1f s" % render(a.kiln, scene, shlex.split(a.ref) + ["--aov", "variance"],
                                           ref), flush=True)
    times = {}
    for r in range(a.repeats):
        for label, kiln, args, points in variants:
            for p in points:
                base = os.path.join(a.out, "%s.%s" % (label, p))
                t = render(kiln, scene, shlex.split(args.replace("{p}", p)) + ["--aov", "none"], base)
                times.setdefault((label, p), []).append(t)
        print("round %d done" % (r + 1), flush=True)
    series = {}
    print("%-16s %8s %10s %12s" % ("variant", "point", "median s", "relMSE"))
    for label, _, _, points in variants:
        for p in points:
            t = statistics.median(times[(label, p)])
            e = rel_mse(a.kiln, os.path.join(a.out, "%s.%s.exr" % (label, p)), ref + ".exr")
            series.setdefault(label, []).append((t, e))
            print("%-16s %8s %10.3f %12.6g" % (label, p, t, e))
    first = variants[0][0]
    errors = [e for _, e in series[first]]
    levels = [errors[(len(errors) - 1) // 2], errors[-1]]
    print("\ntime to reach the error of %s at its middle and last points (ratio to %s):" % (first, first))
    for level in levels:
        base, _ = time_at(series[first], level)
        cells = []
        for label, _, _, _ in variants:
            t, mark = time_at(series[label], level)
            cells.append("%s %.2fs%s (%.2f)" % (label, t, mark, t / base))
        print("relMSE %.3g: %s" % (level, "  ".join(cells)))


if __name__ == "__main__":
    main()
