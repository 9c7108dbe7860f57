#!/usr/bin/env bash
# The equal-error benchmark in one run (a benchmark, not a test): kiln against Blender's Cycles on
# the comparison scenes (tools/peer_bench.py: sampling time only on both sides, set-up reported
# apart, references with their own seed, matched bounces, interleaved repeats, medians, the load
# average at every step), then against the CS184 course program on CBbunny
# (tools/peer/cs184_bench.py; CS184=0 leaves it out), with the settings docs/performance.md quotes.
# References in OUT are reused when made at the same size, spp and seed (by this build: delete them
# after a change to the estimator); the tables are collected in OUT/summary.md.
#   [SCENES="lucy_env ..."] [CS184=0] tools/peer/equal_error.sh [OUT] [extra peer_bench.py arguments]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/equal-error}
shift || true
mkdir -p "$out"
scenes=${SCENES:-lucy_env glossy_env room_uplight box_bunny box_metal}
# Two repeats unless the extra arguments name their own (given once, so each table's command line
# reads as it ran).
repeats=(--repeats 2)
for arg in "$@"; do case $arg in --repeats | --repeats=*) repeats=() ;; esac; done
start=$(date -u '+%Y-%m-%d %H:%M')
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
for scene in $scenes; do
  tools/peer_bench.py --scene "$scene" --spp 16,64,256 --ref-spp 1024 "${repeats[@]}" --samplers sobol \
    --out "$out" "$@"
done
# The course program may not build here (tools/peer/build_cs184.sh needs X11 headers): the Cycles
# tables are still collected, and the summary says why the CS184 part is missing.
cs184_status=0
if [ "${CS184:-1}" != 0 ]; then
  tools/peer/cs184_bench.py --course-spp 8,32,128 --kiln-spp 2,8,32 --repeats 2 \
    --out "$out/cs184" || cs184_status=$?
fi
{
  echo "# Equal-error benchmark, $start to $(date -u '+%H:%M') UTC (load average at the start: $load_start; at the end: $(cut -d' ' -f1-3 /proc/loadavg))"
  echo; echo "CPU: $(grep -m1 '^model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores (the ratios move with the machine)"
  for scene in $scenes; do
    echo; echo "## $scene"; echo; cat "$out/$scene.md"
  done
  if [ "${CS184:-1}" != 0 ]; then
    echo; echo "## CS184 program, CBbunny"; echo
    if [ "$cs184_status" = 0 ]; then
      cat "$out/cs184/cs184.md"
    else
      echo "Not measured: tools/peer/cs184_bench.py exited $cs184_status (the course program is built by tools/peer/build_cs184.sh)."
    fi
  fi
} >"$out/summary.md"
cat "$out/summary.md"
exit "$cs184_status"
