#!/usr/bin/env bash
# What a batch turntable costs against one frame of it (issue #28: a batch loads each scene once).
# Alternates (one, batch, one, batch, ...) the wall time of
#   one:   kiln render MESH -r W H -s 1 --turntable N --frame 1        (load, build, render, write)
#   batch: kiln batch JOB.json, the N frames of the same turntable     (one child, one load and build)
# and prints both medians, their ratio and the load average (a benchmark, not a test; docs/farm.md).
#   tools/batch_load_bench.sh [MESH] [RUNS] [FRAMES]      KILN=path/to/kiln (default build/kiln)
set -euo pipefail
cd "$(dirname "$0")/.."
K=$(realpath "${KILN:-build/kiln}")
MESH=$(realpath "${1:-../shared/meshes/igea_subdiv1_1M.ply}")
RUNS=${2:-5}
FRAMES=${3:-8}
OPTS=(-r 64 48 -s 1)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/kiln-batch-bench-XXXX")
trap 'rm -rf "$WORK"' EXIT
cat >"$WORK/job.json" <<EOF
{"output": "frames/{frame:03}", "scenes": ["$MESH"], "args": ["-r", 64, 48, "-s", 1],
 "cameras": [{"turntable": $FRAMES}]}
EOF

now() { date +%s.%N; }
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}'; }
run_one() { "$K" render "$MESH" "${OPTS[@]}" --turntable "$FRAMES" --frame 1 -q -o "$WORK/one"; }
run_batch() { rm -rf "$WORK/frames"; "$K" batch "$WORK/job.json" -q >/dev/null 2>"$WORK/batch.log"; }

echo "kiln $K; mesh $MESH; ${OPTS[*]}; $FRAMES frames; $RUNS runs each; load average $(cut -d' ' -f1-3 /proc/loadavg)"
run_one 2>/dev/null  # warm-up: the mesh in the page cache
one=() batch=()
for ((i = 1; i <= RUNS; i++)); do
  t0=$(now); run_one 2>/dev/null; t1=$(now)
  run_batch; t2=$(now)
  one+=("$(echo "$t1 - $t0" | bc)") batch+=("$(echo "$t2 - $t1" | bc)")
  echo "run $i: one frame ${one[-1]} s, batch of $FRAMES ${batch[-1]} s"
done
grep -o "this process: [0-9]* renders, [0-9]* scene loads, [0-9]* accelerator builds" "$WORK/batch.log" | tail -n1
m1=$(printf '%s\n' "${one[@]}" | median) mb=$(printf '%s\n' "${batch[@]}" | median)
echo "median: one frame $m1 s, batch of $FRAMES frames $mb s, ratio $(echo "scale=3; $mb / $m1" | bc)"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
