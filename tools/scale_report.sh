#!/usr/bin/env bash
# Generates the scale scenes (in out/scale, not tracked) and runs `kiln bench scale` on each in its own
# process, so the peak-memory column is that scene's. Prints the table docs/scale.md quotes.
set -euo pipefail
cd "$(dirname "$0")/.."
M=../shared/meshes
mkdir -p out/scale
[ -f out/scale/igea_17M.ply ] || build/kiln tools subdivide $M/igea.ply out/scale/igea_17M.ply --levels 3
# The Lucy ladder is one surface at every size (midpoint subdivision does not move it), so its rows
# differ only in triangle count.
[ -f out/scale/lucy_1.6M.ply ] || build/kiln tools subdivide $M/lucy.obj out/scale/lucy_1.6M.ply --levels 2
[ -f out/scale/lucy_6.4M.obj ] || build/kiln tools subdivide $M/lucy.obj out/scale/lucy_6.4M.obj --levels 3
[ -f out/scale/lucy_26M.ply ] || build/kiln tools subdivide $M/lucy.obj out/scale/lucy_26M.ply --levels 4
[ -f out/scale/lucy_102M.ply ] || build/kiln tools subdivide $M/lucy.obj out/scale/lucy_102M.ply --levels 5
cat > out/scale/lucy_field_100M.kiln <<KILN
<kiln-scene>
  <material name="white" albedo="0.75 0.75 0.75"/>
  <instances file="../../$M/lucy.obj" material="white" grid="10 10 10" spacing="1.2"><fit center="0 0 0" size="1"/></instances>
  <light kind="directional" direction="0.4 -1 -0.3" radiance="2 2 2"/>
  <light kind="ambient" radiance="0.3 0.3 0.3"/>
</kiln-scene>
KILN
first=1
for scene in $M/igea_subdiv1_1M.ply out/scale/igea_17M.ply out/scale/lucy_1.6M.ply out/scale/lucy_6.4M.obj \
    out/scale/lucy_26M.ply out/scale/lucy_102M.ply out/scale/lucy_field_100M.kiln; do
  extra=()
  case "$scene" in *.obj) extra=(--compare-assimp) ;; esac
  if [ $first = 1 ]; then build/kiln bench scale "$scene" "${extra[@]}"; first=0
  else build/kiln bench scale "$scene" "${extra[@]}" | tail -n +2; fi
done
