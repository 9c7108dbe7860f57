#!/usr/bin/env bash
# What a batch turntable costs against one frame of it (issue #28: a batch loads each scene once).
# Alternates (one, batch, child, one, batch, child, ...) the wall time of
#   one:   kiln render MESH -r W H -s 1 --turntable N --frame 1        (load, build, render, write)
#   batch: kiln batch JOB.json, the N frames of the same turntable     (one child, one load and build)
#   child: the batch's child alone, kiln render-frames with the N renders (the batch less its own
#          process start-up, job file reading and checks)
# and prints the medians of wall and of CPU time (user + sys, children included: steadier than wall
# on a loaded machine), the ratios to one frame and the load average (a benchmark, not a test;
# docs/farm.md).
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

median() { sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}'; }
child=()
for ((k = 0; k < FRAMES; k++)); do
  ((k == 0)) || child+=(--then)
  child+=("$MESH" "${OPTS[@]}" --turntable "$FRAMES" --frame "$k" -o "$WORK/child/$k" --resume
          --checkpoint-every 60 -q)
done
one=("$K" render "$MESH" "${OPTS[@]}" --turntable "$FRAMES" --frame 1 -q -o "$WORK/one")
batch=("$K" batch "$WORK/job.json" --log-level warning)
alone=("$K" render-frames "${child[@]}")
# Appends "WALL CPU" of one run of the command to the file $1 (outputs removed first).
timed() {
  local file=$1; shift
  rm -rf "$WORK/frames" "$WORK/child"; mkdir "$WORK/child"
  /usr/bin/time -f "%e %U %S" -o "$file.t" "$@" >/dev/null 2>"$WORK/log"
  awk '{print $1, $2 + $3}' "$file.t" >>"$file"
}
col() { cut -d' ' -f"$2" "$WORK/$1" | median; }

echo "kiln $K; mesh $MESH; ${OPTS[*]}; $FRAMES frames; $RUNS runs each; load average $(cut -d' ' -f1-3 /proc/loadavg)"
timed "$WORK/warm" "${one[@]}"  # the mesh in the page cache
for ((i = 1; i <= RUNS; i++)); do
  timed "$WORK/t_one" "${one[@]}"
  timed "$WORK/t_batch" "${batch[@]}"
  # (-q keeps the child's own count quiet; the batch's plan line says how many loads it makes.)
  grep -o "[0-9]* renders from one scene load" "$WORK/log" | tail -n1 || true
  timed "$WORK/t_alone" "${alone[@]}"
  echo "run $i (wall, CPU s): one frame $(tail -n1 "$WORK/t_one"); batch $(tail -n1 "$WORK/t_batch"); child alone $(tail -n1 "$WORK/t_alone")"
done
for what in wall CPU; do
  c=$([[ $what == wall ]] && echo 1 || echo 2)
  m1=$(col t_one "$c") mb=$(col t_batch "$c") mc=$(col t_alone "$c")
  echo "median $what: one frame $m1 s; batch of $FRAMES $mb s, ratio $(echo "scale=3; $mb / $m1" | bc);" \
    "its child alone $mc s, ratio $(echo "scale=3; $mc / $m1" | bc)"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
