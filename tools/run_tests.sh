#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (ctest). Used by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900
