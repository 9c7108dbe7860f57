#!/usr/bin/env bash
# Renders the same set of scenes with two kiln binaries and compares every EXR channel of every
# pixel (idiff, zero tolerance): the check that a refactor leaves images bit-identical.
#   tools/images_identical.sh OLD_KILN NEW_KILN [OUTDIR]
# (A kiln binary copied elsewhere as OLD_KILN needs its kiln_image.so copied beside it.)
# The set: CS184 Lambertian, mirror + glass, microfacet, bounce-only, -H probes, BSDF-only and
# light-only direct light, camera-only emitters, point lights, plan general, forced guiding, and
# kiln's own textured glTF, principled grid, normal map, alpha blend, metallic-roughness texture,
# emissive texture and an environment-lit mesh, with AOVs.
set -euo pipefail
old=$1 new=$2 out=${3:-$(mktemp -d)}
S=$(cd "$(dirname "$0")/.." && pwd)/../shared/scenes/cs184/sky
M=$(cd "$(dirname "$0")/.." && pwd)/scenes
E=$(cd "$(dirname "$0")/.." && pwd)/../shared/envmaps/studio.exr
renders=(
  "lamb|$S/CBspheres_lambertian.dae -r 96 72 -s 16 -m 5"
  "glass|$S/CBspheres.dae -r 96 72 -s 16 -m 6"
  "micro|$S/CBbunny_microfacet_cu.dae -r 96 72 -s 16"
  "env|$S/bunny_microfacet_cu_unlit.dae -e $E -r 96 72 -s 16"
  "gltf|$M/assets/textured.gltf -r 96 72 -s 16"
  "grid|$M/metal_rough/grid.kiln -r 96 72 -s 8"
  "nmap|$M/assets/maps_normal.kiln -r 96 72 -s 8"
  "alpha|$M/assets/maps_alpha_blend.kiln -r 96 72 -s 8"
  "mrtex|$M/assets/metal_rough_texture.gltf -r 96 72 -s 8 --aov all"
  "alag|$S/CBspheres_microfacet_al_ag.dae -r 96 72 -s 8 --aov albedo,direct,indirect"
  "gems|$S/CBgems.dae -r 96 72 -s 8"
  "emis|$M/assets/emissive.gltf -r 96 72 -s 8"
  "hemi|$S/CBspheres_lambertian.dae -H -l 4 -m 3 -r 64 48 -s 4"
  "bsdf|$S/CBspheres.dae --sampling bsdf -r 64 48 -s 8"
  "light|$S/CBspheres.dae --sampling light --heuristic balance --rr fixed -r 64 48 -s 8"
  "cam|$S/CBbunny.dae --emitters camera -m 4 -r 64 48 -s 8"
  "bounce|$S/CBspheres_lambertian.dae --bounce-only -m 3 -r 64 48 -s 8 --aov direct,indirect"
  "general|$S/CBspheres.dae --plan general -r 64 48 -s 8 --aov all"
  "guided|$S/CBbunny_microfacet_cu.dae --guiding on -r 64 48 -s 8"
  "point|$S/bunny.dae -r 64 48 -s 8"
)
mkdir -p "$out/old" "$out/new"
differ=0
for r in "${renders[@]}"; do
  name=${r%%|*} args=${r#*|}
  # shellcheck disable=SC2086
  "$old" render $args -t 2 -q -o "$out/old/$name" 2>/dev/null
  # shellcheck disable=SC2086
  "$new" render $args -t 2 -q -o "$out/new/$name" 2>/dev/null
  if idiff -q -fail 0 -failpercent 0 -warn 0 -a "$out/old/$name.exr" "$out/new/$name.exr" \
    >/dev/null 2>&1; then
    echo "identical  $name"
  else
    echo "DIFFERENT  $name"
    differ=1
  fi
done
exit $differ
