#!/usr/bin/env bash
# Builds the CS184 comparison program (a complete student implementation of the course PathTracer,
# github fy-meng/cs184-p3-1-pathtracer) in a scratch directory outside the repository; never vendored.
#   tools/peer/build_cs184.sh [SOURCE_GIT_DIR] [SCRATCH_DIR]   (prints the path of the binary)
# SOURCE_GIT_DIR is a bare clone (the default is the mirror the session's `fetch` tool made); the
# repository's large .dae files are not needed (the course scenes come from ../shared) and are left out.
# Needs the X11 development headers its bundled GLFW builds against (Debian: libxrandr-dev
# libxinerama-dev libxcursor-dev libxi-dev libgl-dev libfreetype-dev); it renders headless with -f.
set -euo pipefail
src_git=${1:-/work/.mirror/fy-meng+cs184-p3-1-pathtracer/repo/.git}
scratch=${2:-/tmp/cs184prog}
bin=$(find "$scratch/build" -name pathtracer -type f -perm -u+x 2>/dev/null | head -1 || true)
if [ -z "$bin" ]; then
  rm -rf "$scratch/src-tree"
  mkdir -p "$scratch/src-tree" "$scratch/build"
  git --git-dir="$src_git" archive HEAD CGL src CMakeLists.txt |
    tar -x -C "$scratch/src-tree"
  cmake -S "$scratch/src-tree" -B "$scratch/build" -DCMAKE_BUILD_TYPE=Release >"$scratch/cmake.log" 2>&1
  cmake --build "$scratch/build" -j2 >"$scratch/build.log" 2>&1 ||
    { tail -30 "$scratch/build.log" >&2; exit 1; }
  bin=$(find "$scratch/build" -name pathtracer -type f -perm -u+x | head -1)
fi
echo "$bin"
