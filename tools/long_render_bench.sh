#!/usr/bin/env bash
# Checkpoint and merge figures for docs/long-renders.md: a 1920x1080 render with the default AOVs
# writes its checkpoint (size, time of the final write, median of 3 runs), then four crop-quadrant
# shards and four sample-range shards of it are merged (read and combine MiB/s, median of 3).
# Usage: tools/long_render_bench.sh [kiln binary] [scene]
set -euo pipefail
cd "$(dirname "$0")/.."
kiln=${1:-build/kiln}
scene=${2:-../shared/scenes/cs184/sky/CBspheres.dae}
res=(${RES:-1920 1080})
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'; }

echo "checkpoint at ${res[0]}x${res[1]}, default AOVs, -s 1:"
for run in 1 2 3; do
  "$kiln" render "$scene" -r "${res[@]}" -s 1 -q -o "$tmp/full" --checkpoint-every 100000 2>&1 |
    sed -n 's/.*checkpoint .*: \([0-9.]*\) MiB written in \([0-9.]*\)s/\1 \2/p'
done >"$tmp/ckpt.txt"
echo "  size $(awk '{print $1}' "$tmp/ckpt.txt" | head -1) MiB, write $(awk '{print $2}' "$tmp/ckpt.txt" | median) s (median of 3: $(awk '{printf "%s ", $2}' "$tmp/ckpt.txt"))"

crop=("0 0.5 0 0.5" "0.5 1 0 0.5" "0 0.5 0.5 1" "0.5 1 0.5 1")
for i in 0 1 2 3; do
  # shellcheck disable=SC2086
  "$kiln" render "$scene" -r "${res[@]}" -s 1 -q -o "$tmp/crop$i" --checkpoint-every 100000 --crop ${crop[$i]} 2>&1 | grep -v "^kiln: \(.* -> \|[0-9]\|peak\|checkpoint\)" || true
  "$kiln" render "$scene" -r "${res[@]}" -q -o "$tmp/range$i" --sample-range "$i" "$((i + 1))" 2>&1 | grep -v "^kiln: \(.* -> \|[0-9]\|peak\|checkpoint\)" || true
done
for kind in crop range; do
  for run in 1 2 3; do
    "$kiln" merge "$tmp/$kind"[0-3].ckpt -o "$tmp/merged-$kind" 2>&1 |
      sed -n 's/.*, \([0-9.]*\) MiB) .*read and combine \([0-9.]*\)s (\([0-9]*\) MiB\/s), write \([0-9.]*\)s/\1 \2 \3 \4/p'
  done >"$tmp/merge-$kind.txt"
  echo "merge of 4 $kind shards: $(awk '{print $1}' "$tmp/merge-$kind.txt" | head -1) MiB read, $(awk '{print $3}' "$tmp/merge-$kind.txt" | median) MiB/s read and combine (median of 3: $(awk '{printf "%s ", $3}' "$tmp/merge-$kind.txt")), EXR+PNG write $(awk '{print $4}' "$tmp/merge-$kind.txt" | median) s"
done
