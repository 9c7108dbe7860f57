#!/usr/bin/env python3
"""kiln against the CS184 program at equal error (a benchmark, not a test).

  tools/peer/cs184_bench.py [--scene ../shared/scenes/cs184/sky/CBbunny.dae] [--size 160 120]
                            [--course-spp 4,8,32] [--kiln-spp 1,2,4,8,16] [--course-ref-spp 256]
                            [--kiln-ref-spp 1024] [--repeats 2] [--light-samples 1] [--max-depth 5]

The CS184 program is a complete student implementation (github fy-meng/cs184-p3-1-pathtracer) built in a
scratch directory by tools/peer/build_cs184.sh. It runs at fixed spp (`-a 64 0`: a batch of 64 and a
tolerance of 0 never stops a pixel early unless its samples are all equal) and writes only a PNG with the
course's display transform (sqrt(2) exposure, gamma 2.2, clamped, truncated to 8 bits). Its field of view
follows -r: at W x H it shows the central W x H pixels of its 800x600 view, so kiln renders 800x600 with
the matching --crop and the same transform (`-f OUT.png --view CS184`, whose code values equal the
course formula), cut to the window. Error: both PNGs read as code values / 255 and compared with
`kiln bench compare` (luminance relMSE, (x - r)^2 / (r^2 + 0.01)), each against its own converged
reference; the PNGs carry no variance, so the reference's own noise is removed by the independent-
estimator rule E|x - r|^2 = e (1 + n / n_ref) (printed raw too). Time: the course program's BVH build + render as it prints them; kiln's build + render. Runs
interleaved (course, kiln per spp), medians. Prints time to reach the course program's errors at its
middle and largest spp, and the ratio course / kiln.
"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.dont_write_bytecode = True  # no __pycache__ in the checkout
sys.path.insert(0, os.path.join(ROOT, "tools"))
from bench_common import time_at  # noqa: E402
from peer_bench import REF_SEED, rel_mse  # noqa: E402


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(fn, *args):
    """(seconds the program reports, CPU seconds of its process): on a machine shared past its cores
    the wall time measures the scheduler as much as the program; the CPU time does not (it counts
    file parsing too, and not the time a thread waits on a lock, which favours the course program)."""
    before = child_cpu()
    wall = fn(*args)
    return wall, child_cpu() - before


def run_course(binary, scene, spp, a, png):
    cmd = [binary, "-t", str(a.threads), "-s", str(spp), "-a", "64", "0", "-l", str(a.light_samples),
           "-m", str(a.max_depth), "-r", str(a.size[0]), str(a.size[1]), "-f", png, scene]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    bvh = float(re.search(r"Building BVH.*?Done! \(([0-9.]+) sec\)", out, re.S).group(1))
    render = float(re.search(r"Rendering\.\.\. 100%! \(([0-9.]+)s\)", out).group(1))
    return bvh + render


def crop_window(a):
    """kiln's --crop fractions for the central size[0] x size[1] pixels of 800x600."""
    w, h = a.size
    x0, y0 = (800 - w) // 2, (600 - h) // 2
    return [x0 / 800, (x0 + w) / 800, y0 / 600, (y0 + h) / 600]


def run_kiln(kiln, scene, spp, a, png, seed=0):
    # the preview PNG of a crop holds the window alone, as the course program's image
    cmd = [kiln, "render", scene, "-r", "800", "600", "--crop"] + ["%.6g" % f for f in crop_window(a)] + [
        "-s", str(spp), "-l", str(a.light_samples), "-m", str(a.max_depth), "-t", str(a.threads),
        "--sampler", a.sampler, "--seed", str(seed), "--aov", "none", "-q", "--view", "CS184",
        "-o", png[:-4], "-f", png]
    err = subprocess.run(cmd, capture_output=True, text=True, check=True).stderr
    m = re.search(r"build ([0-9.]+)s, render ([0-9.]+)s", err)
    return float(m.group(1)) + float(m.group(2))


def code_values(png):
    """The PNG's code values / 255 as a float EXR (no colour conversion) for `kiln bench compare`."""
    exr = png[:-4] + ".codes.exr"
    subprocess.run(["oiiotool", png, "--ch", "R,G,B", "-d", "float", "-o", exr], check=True)
    return exr


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--scene", default=os.path.normpath(
        os.path.join(ROOT, "..", "shared", "scenes", "cs184", "sky", "CBbunny.dae")))
    ap.add_argument("--size", type=int, nargs=2, default=[160, 120])
    ap.add_argument("--course-spp", default="4,8,32")
    ap.add_argument("--kiln-spp", default="1,2,4,8,16")
    ap.add_argument("--course-ref-spp", type=int, default=256)
    ap.add_argument("--kiln-ref-spp", type=int, default=1024)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--light-samples", type=int, default=1)
    ap.add_argument("--max-depth", type=int, default=5)
    ap.add_argument("--sampler", default="sobol")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "peer", "cs184"))
    ap.add_argument("--kiln", default=os.path.join(ROOT, "build", "kiln"))
    ap.add_argument("--course", default="", help="the course binary (default: build it)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    course = a.course or subprocess.run([os.path.join(HERE, "build_cs184.sh")], capture_output=True,
                                        text=True, check=True).stdout.strip().splitlines()[-1]
    scene = os.path.abspath(a.scene)
    course_spp = [int(v) for v in a.course_spp.split(",")]
    kiln_spp = [int(v) for v in a.kiln_spp.split(",")]

    # references are reused by a later run only when they were made at the same size and spp
    size = "%dx%d" % tuple(a.size)
    # kiln's reference has a seed of its own: sharing its first samples with the test renders (a
    # sample is a pure function of the seed and its index) would understate their error.
    refs = {"course": os.path.join(a.out, "ref%d.%s.course.png" % (a.course_ref_spp, size)),
            "kiln": os.path.join(a.out, "ref%d.%s.seed%d.kiln.png" % (a.kiln_ref_spp, size,
                                                                    REF_SEED))}
    if not os.path.exists(refs["course"]):
        run_course(course, scene, a.course_ref_spp, a, refs["course"])
    if not os.path.exists(refs["kiln"]):
        run_kiln(a.kiln, scene, a.kiln_ref_spp, a, refs["kiln"], REF_SEED)
    ref_exr = {k: code_values(v) for k, v in refs.items()}

    rows = []  # (program, spp, median seconds, relMSE, median CPU seconds)
    runs = {"course": (run_course, course, course_spp), "kiln": (run_kiln, a.kiln, kiln_spp)}
    for i in range(max(len(course_spp), len(kiln_spp))):
        times, cpus = {"course": [], "kiln": []}, {"course": [], "kiln": []}
        for _ in range(a.repeats):  # interleaved: course, kiln, course, kiln
            for k, (fn, binary, spps) in runs.items():
                if i < len(spps):
                    png = os.path.join(a.out, "%s.%d.png" % (k, spps[i]))
                    wall, cpu = timed(fn, binary, scene, spps[i], a, png)
                    times[k].append(wall)
                    cpus[k].append(cpu)
        for k, (_, _, spps) in runs.items():
            if i < len(spps):
                png = os.path.join(a.out, "%s.%d.png" % (k, spps[i]))
                raw = rel_mse(a.kiln, code_values(png), ref_exr[k])
                ref_spp = a.course_ref_spp if k == "course" else a.kiln_ref_spp
                rows.append((k, spps[i], statistics.median(times[k]), raw / (1 + spps[i] / ref_spp),
                             statistics.median(cpus[k])))
                print("%-7s %5d spp %9.3f s  relMSE %.5g  CPU %.3f s (raw relMSE %.5g)"
                      % (rows[-1] + (raw,)), flush=True)

    lines = ["| error level (course program at) | time | course program | kiln | course / kiln |",
             "|---|---|---:|---:|---:|"]
    for spp in (course_spp[len(course_spp) // 2], course_spp[-1]):
        level = [r[3] for r in rows if r[0] == "course" and r[1] == spp][0]
        for column, name in ((2, "wall"), (4, "CPU")):
            tc, _ = time_at([(r[column], r[3]) for r in rows if r[0] == "course"], level)
            tk, mark = time_at([(r[column], r[3]) for r in rows if r[0] == "kiln"], level)
            lines.append("| %.4g (%d spp) | %s | %.2f s | %.3f s%s | %.1f |"
                         % (level, spp, name, tc, tk, mark, tc / tk))
    table = "\n".join(lines)
    print("\n" + table)
    with open(os.path.join(a.out, "cs184.md"), "w") as f:
        f.write("`tools/peer/cs184_bench.py %s`\n\n%s\n" % (" ".join(sys.argv[1:]), table))


if __name__ == "__main__":
    main()
