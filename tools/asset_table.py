#!/usr/bin/env python3
"""Imports and renders every model of Assimp's glTF2 and OBJ samples and prints a markdown table:
what kiln rendered (textures used, a lit or black image) or what it refused, and every warning
(what it dropped). docs/import.md holds the table; re-run after importer changes.

    tools/asset_table.py build/kiln [DIR...]     # default: /usr/share/assimp/models/{glTF2,OBJ}
    tools/asset_table.py build/kiln --montage docs/images/assimp_montage.png FILE...

--montage renders the given files at 160 x 120 and tiles them (oiiotool --mosaic), in order, four
to a row.
"""

import argparse
import json
import os
import subprocess
import tempfile

MODELS = "/usr/share/assimp/models"
EXTENSIONS = (".gltf", ".glb", ".obj")


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=120)


def beauty_max(exr):
    """The brightest beauty value (first three channels), from oiiotool's stats."""
    out = run(["oiiotool", exr, "--printstats"]).stdout
    for line in out.splitlines():
        if "Stats Max:" in line:
            return max(float(v) for v in line.split(":")[1].split()[:3])
    return 0.0


def render(kiln, path, out, width, height, spp):
    return run([kiln, "render", path, "-r", str(width), str(height), "-s", str(spp), "-q",
                "-o", out])


def last_error(stderr):
    """kiln's last error line as its plain stderr says it ("kiln: error: ..."); with --json kiln writes
    it as a JSON log event."""
    line = stderr.strip().splitlines()[-1] if stderr.strip() else ""
    try:
        event = json.loads(line)
        return "kiln: %s: %s" % (event["level"], event["message"])
    except (ValueError, KeyError, TypeError):
        return line


def classify(kiln, path, work):
    info = run([kiln, "info", "--json", path])
    if info.returncode != 0:
        return "refused", last_error(info.stderr), []
    doc = json.loads(info.stdout)
    out = os.path.join(work, "model.exr")
    r = render(kiln, path, out, 64, 48, 4)
    if r.returncode != 0:
        return "render failed", r.stderr.strip().splitlines()[-1], doc["warnings"]
    lit = beauty_max(out) > 0
    textures = doc.get("textures", 0)
    what = ("renders" if lit else "**black**") + (", %d texture%s" % (
        textures, "" if textures == 1 else "s") if textures else "")
    return what, "", doc["warnings"]


def short(warnings):
    """Warnings with the long paths cut to the file name, one per distinct text."""
    seen = []
    for w in warnings:
        w = w.replace(MODELS + "/", "")
        if w not in seen:
            seen.append(w)
    return "; ".join(seen).replace("|", "\\|")


def table(kiln, dirs):
    files = sorted(os.path.join(d, f) for top in dirs for d, _, names in os.walk(top)
                   for f in names if f.lower().endswith(EXTENSIONS))
    print("| file | kiln | warnings (what was dropped or approximated) / error |")
    print("|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for path in files:
            what, error, warnings = classify(kiln, path, work)
            detail = error.replace(path + ": ", "") if error else short(warnings)
            print("| %s | %s | %s |" % (os.path.relpath(path, MODELS), what,
                                        detail.replace("|", "\\|")))


def montage(kiln, out, files):
    with tempfile.TemporaryDirectory() as work:
        tiles = []
        for i, path in enumerate(files):
            tile = os.path.join(work, "tile%02d" % i)
            r = render(kiln, path, tile, 160, 120, 64)
            if r.returncode != 0:
                raise SystemExit("%s: %s" % (path, r.stderr.strip()))
            tiles.append(tile + ".png")
        cols = min(4, len(tiles))
        rows = (len(tiles) + cols - 1) // cols
        subprocess.run(["oiiotool"] + tiles + ["--mosaic:pad=2", "%dx%d" % (cols, rows),
                                               "-d", "uint8", "-o", out], check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kiln")
    parser.add_argument("paths", nargs="*")
    parser.add_argument("--montage", metavar="OUT_PNG")
    args = parser.parse_intermixed_args()
    kiln = os.path.abspath(args.kiln)
    if args.montage:
        montage(kiln, args.montage, args.paths)
    else:
        table(kiln, args.paths or [os.path.join(MODELS, "glTF2"), os.path.join(MODELS, "OBJ")])


if __name__ == "__main__":
    main()
