#!/usr/bin/env bash
# Installs what is missing, builds, and renders scenes/cornell.dae to out/cornell.exr + out/cornell.png.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
mkdir -p out
build/kiln render scenes/cornell.dae -o out/cornell -s 64 -m 5 "$@"
