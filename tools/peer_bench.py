#!/usr/bin/env python3
"""Equal-error peer benchmark: time for kiln and for Blender's Cycles to reach the same relative MSE on
the same scene, each against its own converged reference (a benchmark, not a test).

  tools/peer_bench.py [--scene NAME] [--spp 16,64,256] [--ref-spp 1024] [--repeats 2] [--threads 2]
                      [--resolution W H] [--out out/peer] [--samplers sobol]
                      [--variant LABEL=ARGS[@P1,...]]... [--check] [--write-scenes DIR]
                      [--scene-file JSON]

Scenes: lucy_env (an environment-lit mesh), box_bunny (a closed box lit by an emissive ceiling quad, a
diffuse bunny inside), box_metal (the same box, the bunny in rough chrome), glossy_env (a GGX conductor
bunny on a diffuse floor under the environment), room_uplight (a closed room lit only by an uplighter
facing the ceiling, a diffuse bunny on its floor). Before timing, the two converged references are put
side by side (OUT/SCENE.refs.png) and their mean RGB printed: the scenes are identical when those agree
(--check stops there). --write-scenes DIR writes every scene's .kiln (and quads .dae) there and stops
(scenes/peer holds them). --scene-file JSON takes scenes from a file instead, in the same form
(tools/peer/outside_set.json: scenes the set's settings were not tuned on).

A --variant is another kiln series (e.g. "l4=-l 4", or "noise=-s 1024 --noise-threshold {p}@0.2,0.1,0.05":
one point per spp step), its error measured against the first sampler's reference (every variant
converges to the same image). For every spp the renderers run interleaved (kiln per sampler and
variant, then Cycles), --repeats times; times are medians, and the load average is printed at every
step. Error: `kiln bench compare TEST REF --keep-reference-noise` (luminance relMSE, the same formula
for both renderers, neither reference's noise subtracted). Time is sampling time only on both sides:
kiln's `render` figure (the tile loop, with guide training where the plan guides) and Cycles' own
"Rendered N samples in S seconds" (Blender's --debug-cycles report; N is checked). Scene set-up is
reported beside it: kiln's load + build, Cycles' OBJ import and scene build in Python plus its render
call less the sampling (sync, BVH build, the EXR write). Bounces match: kiln -m N is Cycles
max_bounces N - 1. The error levels are Cycles' errors at the middle and the largest spp of the sweep;
each renderer's time to reach a level is interpolated log-log along its own series. Prints a table and
writes OUT/SCENE.md and OUT/SCENE.csv.
"""
import argparse
import csv
import json
import math
import os
import re
import shlex
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
sys.dont_write_bytecode = True  # no __pycache__ in the checkout
sys.path.insert(0, os.path.join(ROOT, "tools", "peer"))
from box import box_quads, floor_quad, room_quads, write_dae  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "tools"))
from bench_common import parse_variant, time_at  # noqa: E402


def obj_bounds(path):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                p = [float(t) for t in line.split()[1:4]]
                lo = [min(a, b) for a, b in zip(lo, p)]
                hi = [max(a, b) for a, b in zip(hi, p)]
    return lo, hi


def fit_matrix(path, center, size, z_up=False):
    """kiln's <fit>: uniform scale so the largest side is `size`, bottom centre (min Y) at `center`;
    z_up: a Z-up mesh stood up first ((x, y, z) -> (x, z, -y))."""
    lo, hi = obj_bounds(path)
    if z_up:
        lo, hi = [lo[0], lo[2], -hi[1]], [hi[0], hi[2], -lo[1]]
    s = size / max(h - l for l, h in zip(lo, hi))
    bottom = [(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2]
    t = [c - s * b for c, b in zip(center, bottom)]
    if z_up:
        return [s, 0, 0, t[0], 0, 0, s, t[1], 0, -s, 0, t[2], 0, 0, 0, 1]
    return [s, 0, 0, t[0], 0, s, 0, t[1], 0, 0, s, t[2], 0, 0, 0, 1]


# A mesh's material: {"albedo": rgb} (Lambert) or {"alpha": a, "eta": rgb, "k": rgb} (kiln's Beckmann
# conductor; Cycles: Glossy BSDF, Beckmann, roughness sqrt(alpha), colour 1, which equals kiln's only when
# its Fresnel is 1 at every angle: eta 0 makes it exactly 1 for any k), or {"principled": {kiln attribute:
# value}} (tools/peer/cycles_principled.py builds its Cycles counterpart).
CHROME = {"alpha": 0.15, "eta": [0.0, 0.0, 0.0], "k": [1.0, 1.0, 1.0]}
GLOSSY = {"alpha": 0.1, "eta": [0.0, 0.0, 0.0], "k": [1.0, 1.0, 1.0]}  # with "microfacet": "ggx"

# The closed box (tools/peer/box.py): 2 wide, 2 high, 3.2 deep, the camera inside near the front wall.
BOX = {"lo": [-1.0, 0.0, -1.0], "hi": [1.0, 2.0, 2.2], "light_half": 0.3, "radiance": [12.0, 12.0, 12.0]}
BOX_CAMERA = {"position": [0.0, 1.0, 2.1], "look_at": [0.0, 0.9, 0.0], "up": [0, 1, 0], "fov": 40.0}

SCENES = {
    # An environment-lit mesh: Lucy, diffuse 0.6, lit only by the courtyard map (issue #21).
    "lucy_env": {
        "meshes": [{"mesh": "meshes/lucy.obj", "material": {"albedo": [0.6, 0.6, 0.6]},
                    "fit": ([0, 0, 0], 1.0)}],
        "camera": {"position": [0.0, 0.55, 1.9], "look_at": [0.0, 0.5, 0.0], "up": [0, 1, 0],
                   "fov": 36.0},
        "environment": "envmaps/courtyard.exr", "resolution": [300, 400], "max_depth": 5,
    },
    # A closed box lit only by an emissive quad in its ceiling, a diffuse bunny inside.
    "box_bunny": {
        "box": BOX, "camera": BOX_CAMERA, "resolution": [400, 300], "max_depth": 5,
        "meshes": [{"mesh": "meshes/stanford-bunny.obj", "material": {"albedo": [0.73, 0.73, 0.73]},
                    "fit": ([0.0, 0.0, -0.1], 1.0)}],
    },
    # Glossy metal: the same box, the bunny in rough chrome (Beckmann alpha 0.15, Fresnel 1).
    "box_metal": {
        "box": BOX, "camera": BOX_CAMERA, "resolution": [400, 300], "max_depth": 5,
        "meshes": [{"mesh": "meshes/stanford-bunny.obj", "material": CHROME,
                    "fit": ([0.0, 0.0, -0.1], 1.2)}],
    },
    # A glossy GGX conductor (alpha 0.1, Fresnel 1) on a diffuse floor, lit only by the courtyard map.
    "glossy_env": {
        "floor": (3.0, [0.5, 0.5, 0.5]), "microfacet": "ggx",
        "meshes": [{"mesh": "meshes/stanford-bunny.obj", "material": GLOSSY,
                    "fit": ([0.0, 0.0, 0.0], 1.0)}],
        "camera": {"position": [0.0, 0.7, 2.3], "look_at": [0.0, 0.4, 0.0], "up": [0, 1, 0],
                   "fov": 32.0},
        "environment": "envmaps/courtyard.exr", "resolution": [400, 300], "max_depth": 5,
    },
    # An indirect-lit interior: a closed room lit only by an uplighter (an emitting pedestal top facing
    # the ceiling, in the back left corner), a diffuse bunny on the floor.
    "room_uplight": {
        "room": {"lo": [-1.5, 0.0, -1.5], "hi": [1.5, 2.4, 2.0], "pedestal_xz": [-1.0, -1.0],
                 "half": 0.15, "height": 0.9, "radiance": [40.0, 36.0, 30.0]},
        "meshes": [{"mesh": "meshes/stanford-bunny.obj", "material": {"albedo": [0.73, 0.73, 0.73]},
                    "fit": ([0.2, 0.0, -0.3], 0.9)}],
        "camera": {"position": [0.0, 1.3, 1.9], "look_at": [-0.1, 0.8, 0.0], "up": [0, 1, 0],
                   "fov": 55.0},
        "resolution": [400, 300], "max_depth": 6,
    },
}


def scene_quads(s):
    """The scene's quads (name, material, corners): the box, the room or the floor it has, if any."""
    if "box" in s:
        b = s["box"]
        return box_quads(b["lo"], b["hi"], b["light_half"], b["radiance"])
    if "room" in s:
        r = s["room"]
        return room_quads(r["lo"], r["hi"], r["pedestal_xz"], r["half"], r["height"], r["radiance"])
    if "floor" in s:
        return floor_quad(*s["floor"])
    return []


def kiln_options(s):
    """kiln render options the scene needs besides its file (the environment, the microfacet model)."""
    env = ["--env", os.path.join(SHARED, s["environment"])] if s.get("environment") else []
    return env + (["--microfacet", s["microfacet"]] if s.get("microfacet") else [])


def kiln_attribute(value):
    return " ".join("%g" % v for v in value) if isinstance(value, list) else "%g" % value


def kiln_material(name, m):
    if "principled" in m:  # kiln's attribute names (docs/kiln-scene.md); Cycles maps them itself
        return '<material name="%s" kind="principled" %s/>' % (name, " ".join(
            '%s="%s"' % (k, kiln_attribute(v)) for k, v in m["principled"].items()))
    if "albedo" in m:
        return '<material name="%s" albedo="%s"/>' % (name, " ".join(map(str, m["albedo"])))
    return '<material name="%s" kind="microfacet" alpha="%g" eta="%s" k="%s"/>' % (
        name, m["alpha"], " ".join(map(str, m["eta"])), " ".join(map(str, m["k"])))


def describe(name, out, resolution=None, scenes=None):
    """The scene as kiln reads it (.kiln [+ quads .dae] + kiln_options) and as the Cycles script reads
    it (JSON), from SCENES or from `scenes` (tools/peer/material_compare.py's). The .kiln names its
    files relative to its own folder."""
    s = dict((scenes or SCENES)[name])
    if resolution:
        s["resolution"] = resolution
    cam = s["camera"]
    desc = {"meshes": [], "camera": cam, "resolution": s["resolution"],
            # kiln's -m counts path vertices after the camera (1 = direct light); Cycles' bounces
            # count indirect bounces (0 = direct light).
            "max_bounces": s["max_depth"] - 1, "microfacet": s.get("microfacet", "beckmann")}
    opts = " ".join(os.path.relpath(o, out) if o.startswith(SHARED) else o for o in kiln_options(s))
    lines = ["<kiln-scene>", "  <!-- %s: kiln render %s.kiln %s-m %d -->"
             % (name, name, opts + " " if opts else "", s["max_depth"])]
    quads = scene_quads(s)
    if quads:
        write_dae(os.path.join(out, name + ".quads.dae"), quads)
        lines.append('  <include file="%s.quads.dae"/>' % name)
        desc["quads"] = [{"name": n, "material": m, "corners": c} for n, m, c in quads]
    for i, m in enumerate(s["meshes"]):
        mesh = os.path.join(SHARED, m["mesh"])
        matrix = fit_matrix(mesh, *m["fit"], z_up=m.get("z_up", False))
        lines.append("  " + kiln_material("m%d" % i, m["material"]))
        lines.append('  <mesh file="%s" material="m%d"><matrix values="%s"/></mesh>'
                     % (os.path.relpath(mesh, out), i, " ".join("%.9g" % v for v in matrix)))
        desc["meshes"].append({"file": mesh, "matrix": matrix, "material": m["material"]})
    lines.append('  <camera position="%s" look-at="%s" up="%s" fov="%g"/>\n</kiln-scene>\n'
                 % (" ".join(map(str, cam["position"])), " ".join(map(str, cam["look_at"])),
                    " ".join(map(str, cam["up"])), cam["fov"]))
    kiln_path = os.path.join(out, name + ".kiln")
    with open(kiln_path, "w") as f:
        f.write("\n".join(lines))
    if s.get("environment"):
        desc["environment"] = os.path.join(SHARED, s["environment"])
    json_path = os.path.join(out, name + ".json")
    with open(json_path, "w") as f:
        json.dump(desc, f)
    return kiln_path, json_path, s


def run_kiln(kiln, scene_path, s, args, threads, out_base):
    """One kiln render of the scene with ARGS (a list: sampler, spp, a variant's options):
    (sampling seconds, set-up seconds, EXR)."""
    w, h = s["resolution"]
    cmd = [kiln, "render", scene_path] + kiln_options(s) + [
        "-r", str(w), str(h), "-m", str(s["max_depth"]), "-t", str(threads),
        "--aov", "none", "-q", "-o", out_base] + args
    err = subprocess.run(cmd, capture_output=True, text=True, check=True).stderr
    m = re.search(r"time load ([0-9.]+)s, build ([0-9.]+)s, render ([0-9.]+)s", err)
    return float(m.group(3)), float(m.group(1)) + float(m.group(2)), out_base + ".exr"


def run_cycles(blender, json_path, spp, threads, out_path, seed=7):
    """One Cycles render: (sampling seconds, set-up seconds, EXR). Sampling: Cycles' own "Rendered N
    samples in S seconds" (--debug-cycles); set-up: the scene built in Python and the render call
    less the sampling."""
    script = os.path.join(ROOT, "tools", "peer", "cycles_scene.py")
    cmd = [blender, "-b", "--factory-startup", "--debug-cycles", "--python", script, "--",
           json_path, str(spp), str(threads), out_path, str(seed)]
    res = subprocess.run(cmd, capture_output=True, text=True)
    call = re.search(r"kiln-peer: render_seconds ([0-9.]+)", res.stdout)
    scene = re.search(r"kiln-peer: scene_seconds ([0-9.]+)", res.stdout)
    sampled = re.findall(r"^Rendered (\d+) samples in ([0-9.]+) seconds", res.stdout + res.stderr,
                         re.M)
    if res.returncode != 0 or not call or not scene or not sampled:
        sys.exit("Cycles failed:\n" + res.stdout[-3000:] + res.stderr[-3000:])
    n, seconds = int(sampled[-1][0]), float(sampled[-1][1])
    if n != spp:
        sys.exit("Cycles rendered %d samples, not %d" % (n, spp))
    return seconds, float(scene.group(1)) + float(call.group(1)) - seconds, out_path


def load_average():
    return " ".join("%.1f" % v for v in os.getloadavg())


def cpu_model():
    """The CPU the run took its times on: the ratio to Cycles moves with it (docs/performance.md,
    2026-11-28: the same binaries read glossy_env 0.44 on an AMD EPYC and 0.52 on the machine before)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def rel_mse(kiln, test, ref):
    out = subprocess.run([kiln, "bench", "compare", test, ref, "--keep-reference-noise"],
                         capture_output=True, text=True, check=True).stdout
    return float(re.search(r"relmse ([0-9.eE+-]+)", out).group(1))


def mean_rgb(exr):
    out = subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "--printstats"], capture_output=True,
                         text=True, check=True).stdout
    return [float(v) for v in re.search(r"Stats Avg: ([0-9.eE+-]+) ([0-9.eE+-]+) ([0-9.eE+-]+)",
                                        out).groups()]


def complete_kiln_exr(path, spp):
    """Whether a kiln EXR exists with all its samples: an interrupted kiln render (SIGTERM) still
    writes its image, with the samples it reached in kiln:mean_spp."""
    if not os.path.exists(path):
        return False
    out = subprocess.run(["oiiotool", "--info", "-v", path], capture_output=True, text=True).stdout
    m = re.search(r"kiln:mean_spp: ([0-9.]+)", out)
    return bool(m) and float(m.group(1)) >= spp


def check_references(refs, base):
    """The identical-scene check: both converged references side by side (kiln left, Cycles right,
    sRGB) in BASE.refs.png, and their mean RGB, which must agree within the references' noise."""
    kiln_ref = [v for k, v in refs.items() if k != "cycles"][0]
    subprocess.run(["oiiotool", kiln_ref, "--ch", "R,G,B", refs["cycles"], "--ch", "R,G,B",
                    "--mosaic", "2x1", "--colorconvert", "linear", "sRGB", "-d", "uint8", "-o",
                    base + ".refs.png"], check=True)
    lines = []
    for k, v in refs.items():
        lines.append("mean RGB %-18s %s" % (k, " ".join("%.5f" % c for c in mean_rgb(v))))
        print(lines[-1], flush=True)
    return lines


REF_SEED = 1007  # test renders use each renderer's default seed (kiln 0, Cycles 7)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--scene", default="lucy_env",
                    help="a scene of the set (%s) or of --scene-file" % ", ".join(sorted(SCENES)))
    ap.add_argument("--scene-file", metavar="JSON",
                    help="scenes outside the set, {name: scene} in SCENES' form (paths under\n"
                         "../shared): to measure on scenes the set was not tuned on")
    ap.add_argument("--spp", default="16,64,256")
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--resolution", type=int, nargs=2, help="override the scene's image size")
    ap.add_argument("--samplers", default="sobol")
    ap.add_argument("--variant", action="append", default=[],
                    help="a kiln variant, LABEL=ARGS[@P1,P2,...] as in tools/estimator_bench.py: one\n"
                         "point per --spp step ({p} in ARGS; default the step's spp); its error is\n"
                         "measured against the reference of the first of --samplers")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "peer"))
    ap.add_argument("--kiln", default=os.path.join(ROOT, "build", "kiln"))
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--check", action="store_true",
                    help="only make the references and compare them (side by side, mean RGB)")
    ap.add_argument("--write-scenes", metavar="DIR",
                    help="write every scene's .kiln and quads .dae into DIR and stop")
    a = ap.parse_args()
    if a.repeats < 2:
        sys.exit("--repeats: at least 2 (medians of interleaved pairs)")
    scenes = SCENES
    if a.scene_file:
        with open(a.scene_file) as f:
            scenes = json.load(f)
    if a.write_scenes:
        os.makedirs(a.write_scenes, exist_ok=True)
        for name in sorted(scenes):
            # the Cycles JSON names absolute paths
            os.remove(describe(name, a.write_scenes, scenes=scenes)[1])
        return
    os.makedirs(a.out, exist_ok=True)
    spps = [int(v) for v in a.spp.split(",")]
    samplers = a.samplers.split(",")
    if a.scene not in scenes:
        sys.exit("--scene %s: not one of %s" % (a.scene, ", ".join(sorted(scenes))))
    kiln_scene, json_path, s = describe(a.scene, a.out, a.resolution, scenes)
    base = os.path.join(a.out, a.scene)

    # references are reused by a later run only when they were made at the same size and spp
    # References use their own seed: a render sharing its first samples with its reference (both
    # renderers index samples the same way whatever the count) would understate its error.
    ref_tag = ".ref%d.%dx%d.seed%d" % (a.ref_spp, *s["resolution"], REF_SEED)
    refs = {}
    for sampler in samplers:
        ref = base + ref_tag + ".kiln." + sampler
        if not complete_kiln_exr(ref + ".exr", a.ref_spp):
            run_kiln(a.kiln, kiln_scene, s,
                     ["--sampler", sampler, "-s", str(a.ref_spp), "--seed", str(REF_SEED)], a.threads,
                     ref)
        refs["kiln " + sampler] = ref + ".exr"
    refs["cycles"] = base + ref_tag + ".cycles.exr"
    if not os.path.exists(refs["cycles"]):
        run_cycles(a.blender, json_path, a.ref_spp, a.threads, refs["cycles"], REF_SEED)
    means = check_references(refs, base)
    loads = ["CPU %s, %d cores; load average %s at the start" % (cpu_model(), os.cpu_count() or 0,
                                                                 load_average())]
    print(loads[-1], flush=True)
    if a.check:
        return

    # Each kiln series: (label, args with {p}, one point per spp step, its reference).
    series = [("kiln " + x, "--sampler %s -s {p}" % x, [str(p) for p in spps], refs["kiln " + x])
              for x in samplers]
    for text in a.variant:
        label, _, args, points = parse_variant(text, [str(p) for p in spps], a.kiln)
        if len(points) != len(spps):
            sys.exit("variant %s: %d points for %d spp steps" % (label, len(points), len(spps)))
        series.append(("kiln " + label, args, points, refs["kiln " + samplers[0]]))
    rows = []  # (renderer, spp step, median sampling seconds, relMSE, median set-up seconds)
    for step, spp in enumerate(spps):
        times = {label: [] for label, *_ in series}
        times["cycles"] = []
        setups = {k: [] for k in times}
        images = {}
        for _ in range(a.repeats):  # interleaved: A B C, A B C, ...
            for n, (label, args, points, _) in enumerate(series):
                t, setup, img = run_kiln(a.kiln, kiln_scene, s,
                                         shlex.split(args.replace("{p}", points[step])), a.threads,
                                         "%s.kiln.v%d.%d" % (base, n, spp))
                times[label].append(t)
                setups[label].append(setup)
                images[label] = img
            t, setup, img = run_cycles(a.blender, json_path, spp, a.threads,
                                       "%s.cycles.%d.exr" % (base, spp))
            times["cycles"].append(t)
            setups["cycles"].append(setup)
            images["cycles"] = img
        for label, *_, ref in series + [("cycles", refs["cycles"])]:
            rows.append((label, spp, statistics.median(times[label]),
                         rel_mse(a.kiln, images[label], ref), statistics.median(setups[label])))
            print("%-18s %5d spp %8.3f s  relMSE %.5g  set-up %.3f s" % rows[-1], flush=True)
        loads.append("load average %s after %d spp" % (load_average(), spp))
        print(loads[-1], flush=True)

    table = summary_table(rows, [label for label, *_ in series], spps)
    print("\n" + table)
    with open(base + ".csv", "w", newline="") as f:
        csv.writer(f).writerows([("renderer", "spp", "median_sampling_seconds", "relmse",
                                  "median_setup_seconds")] + rows)
    with open(base + ".md", "w") as f:
        f.write("`tools/peer_bench.py %s`\n\n%s\n\n%s\n\n%s\n"
                % (" ".join(sys.argv[1:]), table, "\n".join(means), "; ".join(loads)))


def summary_table(rows, kiln_labels, spps):
    """Per error level (Cycles' at the middle and the largest spp), each renderer's sampling time to
    reach it and its ratio to Cycles'; then each renderer's errors, sampling time per sample at the
    largest spp (and its ratio to Cycles') and median set-up."""
    cycles = [(t, e) for k, _, t, e, _ in rows if k == "cycles"]
    marks = (spps[len(spps) // 2], spps[-1])
    levels = [e for k, spp, t, e, _ in rows if k == "cycles" and spp in marks]
    lines = ["| error level (Cycles at) | renderer | sampling time to reach | / Cycles |",
             "|---|---|---:|---:|"]
    for level, spp in zip(levels, marks):
        tc, _ = time_at(cycles, level)
        for k in kiln_labels + ["cycles"]:
            tk, mark = time_at([(t, e) for kk, _, t, e, _ in rows if kk == k], level)
            lines.append("| %.4g (%d spp) | %s | %.3f s%s | %.2f |" % (level, spp, k, tk, mark, tk / tc))
    per_sample = {k: t / spp for k, spp, t, _, _ in rows if spp == spps[-1]}
    lines += ["", "| renderer | relMSE at %s spp | sampling s at %s spp | per sample / Cycles' (%d spp) "
              "| set-up s (median) |" % ("/".join(map(str, spps)), "/".join(map(str, spps)), spps[-1]),
              "|---|---|---|---:|---:|"]
    for k in kiln_labels + ["cycles"]:
        mine = [r for r in rows if r[0] == k]
        lines.append("| %s | %s | %s | %.2f | %.3f |" % (
            k, " / ".join("%.3g" % r[3] for r in mine), " / ".join("%.3f" % r[2] for r in mine),
            per_sample[k] / per_sample["cycles"], statistics.median(r[4] for r in mine)))
    return "\n".join(lines)


if __name__ == "__main__":
    main()
