#!/usr/bin/env bash
# Installs the Debian packages kiln needs (only those missing) and builds kiln in build/, warnings as
# errors (KILN_WERROR: the README's commands and .ci/run build what CI builds).
# Idempotent: a second run with everything present costs a dpkg query and an incremental build.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config
  libembree-dev libopenimageio-dev openimageio-tools libopenexr-dev openexr
  libopencolorio-dev opencolorio-tools libtbb-dev libassimp-dev libgtest-dev
  libpugixml-dev zlib1g-dev libpng-dev libmurmurhash-dev nlohmann-json3-dev libfmt-dev libcli11-dev help2man
  assimp-testmodels
  python3-dev pybind11-dev python3-numpy  # the kiln Python module (docs/python.md)
  python3-pytest python3-openimageio python3-matplotlib  # its tests and the walkthrough
  slurmctld slurmd slurm-client munge)  # the farm tests' local cluster (tools/slurm_local.sh)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "kiln setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DKILN_WERROR=ON >/dev/null
cmake --build build -j"$(nproc)"
