#!/usr/bin/env bash
# The compositing walkthrough of docs/output.md: renders two scenes and composites them with
# oiiotool alone, writing the pictures into docs/compositing/. Usage: tools/compositing_example.sh
set -euo pipefail
cd "$(dirname "$0")/.."
kiln=${KILN:-build/kiln}
shared=${KILN_SHARED:-../shared}
out=docs/compositing
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
config=(--colorconfig color/config.ocio)
show=(--ociodisplay:from=lin_rec709 sRGB Standard)

# 1. Renders: the CS184 spheres (open to the sky) and the Stanford bunny against a sunset,
#    with a transparent background, Z and Cryptomatte.
"$kiln" render "$shared/scenes/cs184/sky/CBspheres.dae" -r 320 240 -s 64 -q \
  --aov default,crypto_object,crypto_material -o "$work/spheres"
"$kiln" render "$shared/meshes/stanford-bunny.obj" --env "$shared/envmaps/sunset.exr" \
  -r 320 240 -s 64 -q --transparent --aov default,crypto_object -o "$work/bunny"

# 2. The premultiplied beauty over a backdrop (Porter-Duff over), then the display transform.
oiiotool "${config[@]}" "$work/bunny.exr" --ch R,G,B,A \
  --pattern checker:width=20:height=20:color1=0.30,0.30,0.32,1:color2=0.08,0.08,0.1,1 320x240 4 \
  --over --ch R,G,B "${show[@]}" -o "$out/bunny_over_checker.png"
oiiotool "$work/bunny.exr" --ch A -o "$out/bunny_alpha.png"

# 3. Depth: Z (distance along the ray, +inf where nothing was hit) mapped near..far to turbo.
oiiotool "$work/spheres.exr" --ch Z --subc 3.8 --mulc 0.45 --clamp:min=0:max=1 --colormap turbo \
  -o "$out/spheres_depth.png"

# 4. A Cryptomatte matte: the coverage of every rank whose id equals the object's (from the
#    manifest), summed. |id - v| * 1e30 is >= 1 for any other id of these magnitudes.
id=$(exrheader "$work/spheres.exr" | grep -o '"leftWall":"[0-9a-f]*"' | cut -d'"' -f4)
value=$(python3 -c "import struct,sys; print(repr(struct.unpack('>f', bytes.fromhex('$id'))[0]))")
args=()
for layer in 00 01 02; do
  for pair in R,G B,A; do
    idc=CryptoObject$layer.${pair%,*} cov=CryptoObject$layer.${pair#*,}
    args+=("$work/spheres.exr" --ch "$idc" --absdiffc "$value" --mulc 1e30 --clamp:min=0:max=1
      --mulc -1 --addc 1 "$work/spheres.exr" --ch "$cov" --mul)
    [ ${#args[@]} -gt 16 ] && args+=(--add)
  done
done
oiiotool "${args[@]}" -o "$out/spheres_matte_leftwall.png"
oiiotool "${config[@]}" "$work/spheres.exr" --ch R,G,B "${show[@]}" -o "$out/spheres_beauty.png"

# 5. The light AOVs rebuild the beauty: emission + direct + indirect - beauty is zero.
oiiotool "$work/spheres.exr" --ch emission.R,emission.G,emission.B \
  "$work/spheres.exr" --ch direct.R,direct.G,direct.B --add \
  "$work/spheres.exr" --ch indirect.R,indirect.G,indirect.B --add --chnames R,G,B \
  "$work/spheres.exr" --ch R,G,B --sub --abs --printstats | grep -E "Max"
echo "pictures in $out"
