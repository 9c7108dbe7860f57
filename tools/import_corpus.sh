#!/usr/bin/env bash
# Runs `kiln info` and a tiny render over every model file under a directory and classifies each:
#   ok           info and render exit 0 and the image is not entirely black
#   clear-error  exit 2 with a one-line error that names the file
#   crash        killed by a signal (SIGSEGV, SIGABRT, ...)
#   hang         still running after the time limit
#   suspicious   exit 0 with an all-black image, or any other exit code / error form
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
  # An image with no light anywhere is a silent failure (camera away, black materials, no light).
  # The first three channels of the EXR are the beauty RGB.
  if oiiotool "$out.exr" --printstats 2>/dev/null |
    awk '/Stats Max:/ { exit !($3 == 0 && $4 == 0 && $5 == 0) } END { if (NR == 0) exit 1 }'; then
    printf 'suspicious\t%s\tblack image\n' "$f"; return
  fi
  printf 'ok\t%s\t\n' "$f"
}
export -f classify

find "$dir" -type f ! -path '*/ReferenceImages/*' |
  grep -viE '\.(png|jpe?g|bmp|tga|dds|gif|tiff?|pcx|txt|md|mtl|bin|material|skeleton|html|xsd|py|sh|license)$' |
  sort | xargs -P "$jobs" -I{} bash -c 'classify "$@"' _ {} "$work" "$kiln" "$limit" >"$log"

echo "import_corpus: $(wc -l <"$log") files under $dir (log: $log)"
for c in ok clear-error crash hang suspicious; do
  printf '  %-12s %d\n' "$c" "$(grep -c "^$c	" "$log")"
done
