#!/usr/bin/env bash
# A 4-shard farm render through the local Slurm cluster against the same render in one process,
# alternated (one, farm, one, farm, ...) and reported as medians and their ratio (docs/farm.md).
#   tools/farm_bench.sh [SCENE] [RUNS]      KILN_FARM_BENCH_BY=samples|region (default samples)
# The farm time runs from `kiln farm submit` to the merged image (or, with KILN_FARM_BENCH_NO_MERGE=1,
# to the last shard done), so it includes scheduling, every shard's scene load and BVH build, and
# the merge job.
set -euo pipefail
cd "$(dirname "$0")/.."
K=$PWD/build/kiln
SCENE=$(realpath "${1:-../shared/scenes/cs184/sky/CBspheres_lambertian.dae}")
RUNS=${2:-3}
BY=${KILN_FARM_BENCH_BY:-samples}
OPTS=(-r 320 240 -s 64)
export KILN_SLURM_DIR=/tmp/kiln-farm-bench KILN_SLURM_CTLD_PORT=26917 KILN_SLURM_SLURMD_PORT=26918
eval "$(tools/slurm_local.sh start)"
WORK=$(mktemp -d /tmp/kiln-farm-bench-XXXX)
trap 'tools/slurm_local.sh stop; rm -rf "$WORK"' EXIT

now() { date +%s.%N; }
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}'; }

# Seconds until `kiln farm status` shows every shard done and the merge done (or no merge asked).
wait_farm() {
  local dir=$1 line failed='[1-9][0-9]* failed|merge: (FAILED|CANCELLED)'
  while :; do
    line=$("$K" farm status "$dir" 2>/dev/null | head -n1 || true)
    if [[ $line == *" 0 running, 0 pending, 0 failed"* ]]; then
      [[ ${KILN_FARM_BENCH_NO_MERGE:-0} == 1 || $line == *"merge: done"* ]] && return 0
    fi
    if [[ $line =~ $failed ]]; then
      "$K" farm status "$dir" >&2
      return 1
    fi
    sleep 0.2
  done
}

one=() farm=()
for ((i = 1; i <= RUNS; i++)); do
  t0=$(now)
  "$K" render "$SCENE" "${OPTS[@]}" -q -o "$WORK/one_$i" 2>/dev/null
  one+=("$(echo "$(now) - $t0" | bc)")
  t0=$(now)
  "$K" farm submit "$SCENE" "${OPTS[@]}" --shards 4 --by "$BY" -d "$WORK/farm_$i" >/dev/null 2>&1
  wait_farm "$WORK/farm_$i"
  farm+=("$(echo "$(now) - $t0" | bc)")
  echo "run $i: one process ${one[-1]} s, 4-shard farm ${farm[-1]} s"
done
a=$(printf '%s\n' "${one[@]}" | median)
b=$(printf '%s\n' "${farm[@]}" | median)
# Per shard: the scene load and build every shard pays, from kiln render's own summary line.
cat "$WORK"/farm_*/logs/shard_*.log | sed -n 's/.*time load \([0-9.]*\)s, build \([0-9.]*\)s, render \([0-9.]*\)s.*/\1 \2 \3/p' |
  awk '{l+=$1; b+=$2; r+=$3; n++} END {printf "per shard (mean of %d): load %.3f s, build %.3f s, render %.3f s\n", n, l/n, b/n, r/n}'
echo "median of $RUNS: one process $a s, 4-shard farm by $BY $b s, farm/one $(echo "scale=2; $b / $a" | bc)"
