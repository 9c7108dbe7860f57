#!/usr/bin/env python3
"""Load time of mesh files under two kiln binaries, interleaved (A B A B ...), medians and ratio.

    tools/bench_load.py BASELINE_KILN NEW_KILN FILE... [--runs N]

Reads "load_seconds" from `kiln info --json` (the importer, validation and recentring, without
process start-up), so a reader change is measured where it happens.
"""
import json
import statistics
import subprocess
import sys


def load_seconds(kiln, path):
    out = subprocess.run([kiln, "info", "--json", path], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)["load_seconds"]


def main():
    args = sys.argv[1:]
    runs = 7
    if "--runs" in args:
        i = args.index("--runs")
        runs = int(args[i + 1])
        del args[i : i + 2]
    if len(args) < 3:
        sys.exit(__doc__)
    base, new, files = args[0], args[1], args[2:]
    print(f"{'file':32} {'baseline s':>11} {'new s':>11} {'new/base':>9}   (median of {runs}, interleaved)")
    for path in files:
        a, b = [], []
        for _ in range(runs):
            a.append(load_seconds(base, path))
            b.append(load_seconds(new, path))
        ma, mb = statistics.median(a), statistics.median(b)
        print(f"{path.split('/')[-1]:32} {ma:11.4f} {mb:11.4f} {mb / ma:9.3f}")


if __name__ == "__main__":
    main()
