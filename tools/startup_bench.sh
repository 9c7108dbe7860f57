#!/usr/bin/env bash
# Where kiln's start-up time goes (issue #28, docs/performance.md "Start-up"): `kiln --version` and
# `kiln info SCENE` against empty programs (main prints one line) linked with
#   all:   exactly kiln's own NEEDED libraries (readelf -d), OpenImageIO among them
#   no-oiio: the same without OpenImageIO, plus OpenEXR and libpng (what EXR/PNG I/O would need)
#   none:  libstdc++ only
# run interleaved (kiln, info, all, no-oiio, none, kiln, ...), RUNS rounds; prints for each the median
# wall and CPU (user + sys) seconds, the shared libraries loaded, and the load average, then the
# dynamic loader's own statistics for kiln --version (a benchmark, not a test).
#   tools/startup_bench.sh [SCENE] [RUNS]        KILN=path/to/kiln (default build/kiln)
set -euo pipefail
cd "$(dirname "$0")/.."
K=$(realpath "${KILN:-build/kiln}")
SCENE=$(realpath "${1:-../shared/meshes/stanford-bunny.obj}")
RUNS=${2:-20}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/kiln-startup-XXXX")
trap 'rm -rf "$WORK"' EXIT

printf '#include <cstdio>\nint main() { std::puts("kiln"); }\n' >"$WORK/empty.cpp"
mapfile -t needed < <(readelf -d "$K" | sed -n 's/.*NEEDED.*\[lib\(.*\)\.so.*\]/\1/p')
all=() light=()
for lib in "${needed[@]}"; do
  case $lib in c | m | gcc_s | stdc++ | ld-linux-x86-64) continue ;; esac
  all+=("-l:lib$lib.so")
  [[ $lib == OpenImageIO* ]] || light+=("-l:lib$lib.so")
done
light+=(-lOpenEXR-3_1 -lpng16)
g++ -O2 "$WORK/empty.cpp" -o "$WORK/all" -Wl,--no-as-needed "${all[@]}"
g++ -O2 "$WORK/empty.cpp" -o "$WORK/no-oiio" -Wl,--no-as-needed "${light[@]}"
g++ -O2 "$WORK/empty.cpp" -o "$WORK/none"

names=("kiln --version" "kiln info" "empty, kiln's libraries" "empty, without OIIO" "empty, libstdc++")
commands=("$K --version" "$K info $SCENE" "$WORK/all" "$WORK/no-oiio" "$WORK/none")
libs=("$(ldd "$K" | wc -l)" "$(ldd "$K" | wc -l)" "$(ldd "$WORK/all" | wc -l)"
      "$(ldd "$WORK/no-oiio" | wc -l)" "$(ldd "$WORK/none" | wc -l)")
echo "kiln $K; scene $SCENE; $RUNS interleaved rounds; load average $(cut -d' ' -f1-3 /proc/loadavg)"
for c in "${commands[@]}"; do $c >/dev/null 2>&1; done  # warm-up: every library in the page cache
for ((r = 1; r <= RUNS; r++)); do
  for i in "${!commands[@]}"; do
    /usr/bin/time -f "%e %U %S" -a -o "$WORK/t$i" ${commands[$i]} >/dev/null 2>&1
  done
done
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}'; }
printf '%-26s %6s %12s %12s\n' "program" "libs" "wall median" "CPU median"
for i in "${!commands[@]}"; do
  wall=$(cut -d' ' -f1 "$WORK/t$i" | median) cpu=$(awk '{print $2 + $3}' "$WORK/t$i" | median)
  printf '%-26s %6s %11ss %11ss\n' "${names[$i]}" "${libs[$i]}" "$wall" "$cpu"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "dynamic loader, kiln --version (LD_DEBUG=statistics):"
LD_DEBUG=statistics "$K" --version 2>&1 >/dev/null | grep -E "total startup|relocation:|number of relocations:|load objects" | head -4
