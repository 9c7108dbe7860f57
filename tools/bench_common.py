"""What the equal-error benchmarks share (tools/estimator_bench.py, tools/peer_bench.py,
tools/peer/cs184_bench.py): the log-log interpolation to a time at an error level and the parser of a
--variant. A leaf module: it imports nothing of tools/, so the benchmarks import it and not each other.
"""
import math
import subprocess
import sys


def time_at(series, level):
    """Log-log interpolation of (time, error) points to the time at which error reaches `level`;
    extrapolated (marked with '*') along the last two points below the smallest error, and along the
    first two above the largest (a level reached before the first point). An error of 0 (at or below
    the reference's own noise, which `kiln bench compare` subtracts unless given
    --keep-reference-noise) measures nothing and is left out."""
    pts = sorted(p for p in series if p[1] > 0)
    if level <= 0:
        return float("nan"), "?"

    def along(p, q):  # the time where the log-log line through p and q meets the level
        (t0, e0), (t1, e1) = p, q
        f = math.log(level / e0) / math.log(e1 / e0)
        return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))

    for p, q in zip(pts, pts[1:]):
        if p[1] >= level >= q[1] and p[1] != q[1]:
            return along(p, q), ""
    if len(pts) >= 2 and level < pts[-1][1]:
        return along(pts[-2], pts[-1]), "*"
    if len(pts) >= 2 and level > pts[0][1] and pts[0][1] != pts[1][1]:
        return along(pts[0], pts[1]), "*"
    return float("nan"), "?"


def parse_variant(text, default_points, kiln):
    """LABEL=[KILN::]ARGS[@P1,P2,...] -> (label, kiln binary, args with {p}, points); ARGS without
    {p} get "-s {p}", and the points default to default_points."""
    label, sep, rest = text.partition("=")
    if not sep:
        sys.exit("--variant takes LABEL=[KILN::]ARGS[@P1,P2,...], got " + repr(text))
    if "::" in rest:
        kiln, rest = rest.split("::", 1)
    args, at, points = rest.partition("@")
    points = points.split(",") if at else list(default_points)
    if "{p}" not in args:
        args += " -s {p}"
    return label, kiln, args, points


def run_kiln(command):
    """Runs a kiln command line (a list) and returns its stderr, where kiln prints its times; exits
    with the command and the end of its stderr when it fails."""
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (run.returncode, " ".join(command), run.stderr[-2000:]))
    return run.stderr
