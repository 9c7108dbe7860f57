#!/usr/bin/env bash
# Builds kiln and its tests with AddressSanitizer + UndefinedBehaviorSanitizer in build-sanitize/
# and runs the tests; any sanitizer report fails the run (UBSan does not recover, ASan halts).
# Usage: tools/sanitize.sh [GTEST_FILTER]
# Default filter: the importer and bad-input tests, the fuzz test (which runs the sanitized kiln
# binary on 180 mutated files) and the far-coordinate tests; pass '*' for the whole suite (about
# 10x slower than Release).
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-'BadInput*:Import*:AssimpFormats*:Cs184*:KilnScene*:ObjReader*:Fuzz*:FarCoordinates*:Framing*'}
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKILN_SANITIZE=ON \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
cmake --build build-sanitize -j"$(nproc)" 2>&1 | grep -E "error|warning" || true
# Leak checking is off: the third-party libraries (OCIO, OIIO, Assimp) keep static allocations
# that LeakSanitizer reports at exit; errors in kiln's own memory use are still reported.
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
./build-sanitize/kiln_tests --gtest_filter="$filter"
