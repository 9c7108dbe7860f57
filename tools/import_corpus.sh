#!/usr/bin/env bash
# Runs `kiln info` and a tiny render over every model file under a directory and classifies each:
#   ok           info and render exit 0 and the image is not dark (mean luminance >= 1e-3)
#   warned-dark  exit 0, the image dark, and kiln's render said why (a black-image, clip-range or
#                black-material warning)
#   clear-error  exit 2 with a one-line error that names the file
#   crash        killed by a signal (SIGSEGV, SIGABRT, ...)
#   hang         still running after the time limit
#   suspicious   exit 0 with a dark image and no warning saying so (silently wrong), or any other
#                exit code / error form
# Usage: tools/import_corpus.sh [DIR] [-j JOBS] [-t SECONDS] [-o LOG]
# Default DIR: /usr/share/assimp/models (Debian assimp-testmodels). Prints one line per file to LOG
# (default corpus.log) and the counts to stdout.
set -uo pipefail
cd "$(dirname "$0")/.."
dir=/usr/share/assimp/models jobs=$(nproc) limit=60 log=corpus.log
[ $# -gt 0 ] && [ "${1#-}" = "$1" ] && { dir=$1; shift; }
while [ $# -gt 0 ]; do
  case $1 in
    -j) jobs=$2; shift 2 ;;
    -t) limit=$2; shift 2 ;;
    -o) log=$2; shift 2 ;;
    *) echo "usage: $0 [DIR] [-j JOBS] [-t SECONDS] [-o LOG]" >&2; exit 2 ;;
  esac
done
kiln=$PWD/build/kiln
[ -x "$kiln" ] || { echo "import_corpus: build kiln first (tools/setup.sh)" >&2; exit 2; }
[ -d "$dir" ] || { echo "import_corpus: no directory $dir (apt-get install assimp-testmodels)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One file: prints "CLASS<tab>FILE<tab>DETAIL".
classify() {
  local f=$1 work=$2 kiln=$3 limit=$4 out rc err
  out=$work/$(echo "$f" | md5sum | cut -c1-16)
  for step in info render; do
    if [ $step = info ]; then
      timeout -s KILL "$limit" "$kiln" info "$f" >/dev/null 2>"$out.err"
    else
      timeout -s KILL "$limit" "$kiln" render "$f" -r 32 24 -s 4 -q -o "$out" >/dev/null 2>"$out.err"
    fi
    rc=$?
    err=$(tr '\n' ' ' <"$out.err" | cut -c1-200)
    if [ $rc -eq 137 ]; then printf 'hang\t%s\t%s after %ss\n' "$f" $step "$limit"; return; fi
    if [ $rc -gt 128 ]; then printf 'crash\t%s\t%s signal %d\n' "$f" $step $((rc - 128)); return; fi
    if [ $rc -eq 2 ] && [ "$(grep -c '' "$out.err")" -eq 1 ] && grep -qF "$f" "$out.err"; then
      printf 'clear-error\t%s\t%s\n' "$f" "$err"; return
    fi
    if [ $rc -ne 0 ]; then printf 'suspicious\t%s\t%s exit %d: %s\n' "$f" $step $rc "$err"; return; fi
  done
  # A dark image (mean luminance under 1e-3, what kiln's own black-image probe calls black: code 3
  # of 255 after sRGB) is a silent failure unless kiln warned why (camera away or clipping
  # everything, black materials, lights too dim). The first three channels are the beauty RGB.
  local mean
  mean=$(oiiotool "$out.exr" --printstats 2>/dev/null |
    awk '/Stats Avg:/ { printf "%.3g", 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5; exit }')
  if [ -z "$mean" ] || awk -v m="$mean" 'BEGIN { exit !(m < 1e-3) }'; then
    if grep -qE 'will look black|show no geometry|diffuse colour is black' "$out.err"; then
      printf 'warned-dark\t%s\tmean %s: %s\n' "$f" "$mean" \
        "$(grep -hE 'will look black|show no geometry|diffuse colour is black' "$out.err" |
          head -1 | cut -c1-200)"; return
    fi
    printf 'suspicious\t%s\tdark image (mean %s), no warning\n' "$f" "$mean"; return
  fi
  printf 'ok\t%s\tmean %s\n' "$f" "$mean"
}
export -f classify

find "$dir" -type f ! -path '*/ReferenceImages/*' |
  grep -viE '\.(png|jpe?g|bmp|tga|dds|gif|tiff?|pcx|txt|md|mtl|bin|material|skeleton|html|xsd|py|sh|license)$' |
  sort | xargs -P "$jobs" -I{} bash -c 'classify "$@"' _ {} "$work" "$kiln" "$limit" >"$log"

echo "import_corpus: $(wc -l <"$log") files under $dir (log: $log)"
for c in ok warned-dark clear-error crash hang suspicious; do
  printf '  %-12s %d\n' "$c" "$(grep -c "^$c	" "$log")"
done
