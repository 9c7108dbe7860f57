#!/usr/bin/env bash
# Builds kiln and its tests with AddressSanitizer + UndefinedBehaviorSanitizer (and -Werror) in
# build-sanitize/ (without the Python module: an ASan runtime cannot load into a plain python3)
# and runs the tests. Fails (non-zero) when the build fails (its errors printed),
# when a test fails, or when any sanitizer report appears, in the test process or in a kiln child
# process it started (reports go to build-sanitize/reports/ and are printed at the end).
# Usage: tools/sanitize.sh [GTEST_FILTER]      (.ci/run runs it with the default filter)
# Default filter (what fits CI's sanitizer budget, README): the importer tests (parameterised ones
# included), bad-input tests and the EXR reader that bypasses OpenImageIO, the fuzz test (which
# runs the sanitized kiln binary on 180 mutated files), the far-coordinate and framing tests,
# checkpoints (kills, resumes, atomic files) and shard merges; pass '*' for the whole suite (about 10x slower than Release).
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-'BadInput*:Import*:*/MeshImport.*:*/Cs184Import.*:PrincipledImport.*:AssimpFormats*:Cs184*:KilnScene*:ObjReader*:PlyTristrips*:OwnScenes*:EnvironmentOption*:ExrRgbInput*:Fuzz*:FarCoordinates*:Framing*:Checkpoint*:AtomicFile*:Merge*'}
dir=build-sanitize

# ccache only where it is installed (a fresh machine has none); an empty launcher also clears one
# an earlier configure left in the cache.
launcher=
command -v ccache >/dev/null 2>&1 && launcher=ccache
mkdir -p "$dir"
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKILN_SANITIZE=ON -DKILN_WERROR=ON -DKILN_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" >"$dir/configure.log" 2>&1 || {
  cat "$dir/configure.log" >&2
  echo "sanitize: configuring $dir failed" >&2
  exit 1
}
log=$dir/build.log
if ! cmake --build "$dir" -j"$(nproc)" >"$log" 2>&1; then
  # The compiler's and linker's messages; the whole log when they are not recognised.
  grep -E -B4 -A8 'error:|Error [0-9]+|undefined reference|ld returned' "$log" >&2 || cat "$log" >&2
  echo "sanitize: the build in $dir failed (full log: $log)" >&2
  exit 1
fi

reports=$PWD/$dir/reports
rm -rf "$reports" && mkdir -p "$reports"
# Leak checking is off: the third-party libraries (OCIO, OIIO, Assimp) keep static allocations
# that LeakSanitizer reports at exit; errors in kiln's own memory use are still reported.
# ASan writes its reports to files (log_path), also those of kiln processes a test starts and whose
# output it keeps. GCC's UBSan (linked with ASan) prints to stderr whatever log_path says, so it
# aborts (SIGABRT: a signal no test takes for success, where its plain exit 1 could pass for kiln's
# "failure" exit) and the output is searched for reports as well.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:halt_on_error=1:log_path=$reports/asan
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:abort_on_error=1
# The tests' scratch folders (TMPDIR/kiln-tests/SUITE.NAME) inside build-sanitize/: a Release suite
# or another checkout's tests running at the same time on this machine use the same names in /tmp.
export TMPDIR=$PWD/$dir/tmp
rm -rf "$TMPDIR" && mkdir -p "$TMPDIR"
status=0
"./$dir/kiln_tests" --gtest_filter="$filter" 2>&1 | tee "$dir/tests.log" || status=$?
if compgen -G "$reports/*" >/dev/null; then
  for r in "$reports"/*; do
    echo "==== sanitizer report $r" >&2
    cat "$r" >&2
  done
  echo "sanitize: AddressSanitizer reports above" >&2
  status=1
fi
if grep -E -q 'runtime error:|ERROR: [A-Za-z]+Sanitizer|SUMMARY: [A-Za-z]+Sanitizer' "$dir/tests.log"; then
  grep -E 'runtime error:|ERROR: [A-Za-z]+Sanitizer|SUMMARY: [A-Za-z]+Sanitizer' "$dir/tests.log" >&2
  echo "sanitize: sanitizer reports in the test output ($dir/tests.log)" >&2
  status=1
fi
if ((status != 0)); then
  echo "sanitize: FAILED (exit $status)" >&2
  exit "$status"
fi
echo "sanitize: passed ($filter)"
