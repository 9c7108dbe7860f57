#!/usr/bin/env bash
# kiln against the CS184 baseline (../shared/docs/CS184_BASELINE.md: 480x360, 64 spp, -l 4 -m 5,
# 2 threads), side by side in one run. The course program's 480x360 is the central 60 % of its
# 800x600 view, so kiln renders that same window (--crop). Each scene: two timed renders, beauty only
# as the course writes, then --traversal-floor: the render's rays traced again with no shading, the
# time no shading speed-up can remove. Prints the table docs/light-transport.md quotes.
set -euo pipefail
cd "$(dirname "$0")/.."
S=../shared/scenes/cs184/sky
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
view=(-r 800 600 --crop 0.2 0.8 0.2 0.8 -s 64 -l 4 -m 5 -t 2 -q --aov none)

printf '%-22s %10s %12s %10s %10s %12s %14s\n' scene "CS184 s" "kiln s" "Mrays" "speed-up" \
  "floor s" "max speed-up"
for entry in "CBspheres_lambertian 41 44" "CBbunny 69 87"; do
  read -r name lo hi <<<"$entry"
  times=() floor="" rays=""
  for run in 1 2 3; do
    extra=()
    [ $run = 3 ] && extra=(--traversal-floor)
    log=$(build/kiln render "$S/$name.dae" "${view[@]}" -o "$out/$name" "${extra[@]}" 2>&1)
    if [ $run -lt 3 ]; then
      times+=("$(sed -n 's/.*render \([0-9.]*\)s,.*/\1/p' <<<"$log")")
      rays=$(sed -n 's/.* samples, \([0-9]*\) rays,.*/\1/p' <<<"$log")
    else
      floor=$(sed -n 's/.*in the same calls: \([0-9.]*\)s .*/\1/p' <<<"$log")
    fi
  done
  fast=$(printf '%s\n' "${times[@]}" | sort -g | head -1)
  slow=$(printf '%s\n' "${times[@]}" | sort -g | tail -1)
  awk -v n="$name" -v lo="$lo" -v hi="$hi" -v f="$fast" -v s="$slow" -v fl="$floor" -v r="$rays" \
    'BEGIN { printf "%-22s %10s %12s %10.1f %10s %12.2f %14s\n", n, lo "-" hi, f "-" s, r / 1e6,
             sprintf("%.1f-%.1fx", lo / s, hi / f), fl, sprintf("%.1f-%.1fx", lo / fl, hi / fl) }'
done
echo
echo "kiln: render time as kiln reports it, two renders; speed-up = CS184 time / kiln time (worst-best);"
echo "floor = the same rays traced alone in the same Embree calls (kiln render ... --traversal-floor);"
echo "max speed-up = CS184 time / floor: what kiln would reach if shading, sampling and film cost nothing."
