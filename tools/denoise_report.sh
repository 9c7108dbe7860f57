#!/usr/bin/env bash
# The figures of docs/denoise.md in one run (a benchmark, not a test): for each scene the spp sweep raw
# and denoised against a 4096-spp reference (`kiln bench accuracy SCENE --denoise`, 128x96), side-by-side
# crops (noisy 16 spp, denoised, reference; 4x nearest, gamma 1/2.2 for display) and, with --speed, the
# 1280x720 env-lit Lucy timing (CPU seconds of the 16-spp render against the denoiser on 2 threads).
#   tools/denoise_report.sh [OUT] [--speed]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/denoise}
mkdir -p "$out"
S=../shared/scenes/cs184/sky
E=../shared/envmaps/courtyard.exr
# The accuracy report's five scenes, the env-lit Lucy and a textured glTF under the same map.
scenes=("$S/CBspheres_lambertian.dae" "$S/CBbunny.dae" "$S/CBspheres.dae" "$S/CBbunny_microfacet_cu.dae"
        "../shared/meshes/igea_subdiv1_1M.ply" "../shared/meshes/lucy.obj --env $E"
        "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf --env $E")
echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
for entry in "${scenes[@]}"; do
  scene=${entry%% *}; extra=${entry#"$scene"}
  name=$(basename "$scene"); name=${name%.*}
  # shellcheck disable=SC2086
  build/kiln bench accuracy "$scene" $extra --denoise --budget 150 -o "$out/$name" > /dev/null
  # shellcheck disable=SC2086
  build/kiln render "$scene" $extra -r 128 96 -s 16 --denoise -q -o "$out/$name-16" 2> /dev/null
  ref=$(ls "$out/$name"/reference-m100-*.exr)
  oiiotool "$out/$name-16.exr" --ch noisy.R,noisy.G,noisy.B --chnames R,G,B \
    "$out/$name-16.exr" --ch R,G,B "$ref" --ch R,G,B --mosaic 3x1 --resize:filter=box 1536x384 \
    --clamp:min=0 --powc 0.4545 -d uint8 -o "$out/$name-crops.png"
  echo "## $name"; echo; cat "$out/$name/summary.md"; echo
done
if [ "${2:-}" = "--speed" ]; then
  # The denoiser against the render it denoises, both timed inside one `render --denoise` process
  # (kiln:render_seconds, kiln:denoise_seconds): the same load weighs on both. Three repeats.
  L=(../shared/meshes/lucy.obj --env "$E" -r 1280 720 -s 16 -t 2 -q)
  for i in 1 2 3; do
    /usr/bin/time -f "render 16 spp: %e s wall, %U s CPU, peak %M KB" build/kiln render "${L[@]}" -o "$out/lucy720" 2>&1 | tail -1
    /usr/bin/time -f "render 16 spp --denoise: %e s wall, %U s CPU, peak %M KB" build/kiln render "${L[@]}" --denoise -o "$out/lucy720d" 2>&1 | tail -1
    oiiotool --info -v "$out/lucy720d.exr" | grep -E "kiln:(render|denoise)_seconds" | tr -s ' ' | tr '\n' ' '; echo
  done
  /usr/bin/time -f "kiln denoise -t 2: %e s wall, %U s CPU, peak %M KB" build/kiln denoise "$out/lucy720d.exr" -t 2 -o "$out/lucy720dd.exr" 2>&1 | tail -1
fi
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
