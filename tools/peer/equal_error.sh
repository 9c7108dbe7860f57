#!/usr/bin/env bash
# The equal-error benchmark in one run (a benchmark, not a test): kiln against Blender's Cycles on
# the three comparison scenes (tools/peer_bench.py), then against the CS184 course program on
# CBbunny (tools/peer/cs184_bench.py), with the settings docs/performance.md quotes. Fresh
# references in OUT (made by this build); the tables are collected in OUT/summary.md.
#   tools/peer/equal_error.sh [OUT] [extra peer_bench.py arguments, e.g. --variant "rr3=--rr-start 3"]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/equal-error}
shift || true
mkdir -p "$out"
start=$(date -u '+%Y-%m-%d %H:%M')
for scene in lucy_env box_bunny box_metal; do
  tools/peer_bench.py --scene "$scene" --resolution 160 120 --spp 16,32,64,128,256 --ref-spp 1024 \
    --repeats 3 --samplers sobol --out "$out" "$@"
done
tools/peer/cs184_bench.py --course-spp 8,32,128 --kiln-spp 2,8,32 --repeats 2 --out "$out/cs184"
{
  echo "# Equal-error benchmark, $start to $(date -u '+%H:%M') UTC (load average at the end: $(cut -d' ' -f1-3 /proc/loadavg))"
  for scene in lucy_env box_bunny box_metal; do
    echo; echo "## $scene"; echo; cat "$out/$scene.md"
  done
  echo; echo "## CS184 program, CBbunny"; echo; cat "$out/cs184/cs184.md"
} >"$out/summary.md"
cat "$out/summary.md"
