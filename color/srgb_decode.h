// sRGB-encoded colour (8-bit images, PNG/JPEG, files tagged sRGB, integer vertex colours) to kiln's
// working space through OpenColorIO: the config kiln follows (color_config.h) converts from its
// sRGB texture colour space (a known name, else the space its texture_paint, matte_paint or
// color_picking role names when that space is sRGB-encoded) to scene_linear, exactly. A config that
// has no such space, or cannot be loaded, falls back to the standard sRGB curve (a warning, once).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace kiln {

// `count` interleaved texels of `channels` floats each: the first three are colour (one channel:
// grey), the rest (alpha) stay as they are.
void decodeSrgbTexels(float* texels, size_t count, int channels);

// The 256 8-bit codes decoded (one pass through the processor): 8-bit colour is mapped through it,
// which is exact and costs a table lookup a value.
std::array<float, 256> srgb8Table();

// `count` 8-bit texels of `channels` codes each to floats: the colour channels (the first three)
// through srgb8Table, the others (alpha) code / 255.
void decodeSrgb8Texels(const uint8_t* codes, float* out, size_t count, int channels);

// One value, as a grey (a run of values: decodeSrgbTexels).
float srgbToLinear(float encoded);

}  // namespace kiln
