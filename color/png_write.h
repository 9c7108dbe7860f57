// 8-bit PNG writing with libpng, through an AtomicFile: the preview needs no OpenImageIO
// (image_module.h).
#pragma once

#include <cstdint>
#include <string>

namespace kiln {

// Writes `codes` (w x h pixels of `channels` 8-bit values: 3 RGB, 4 RGBA, row-major) to path at
// zlib's fastest level (the preview's deflate at libpng's default level 6 was a fifth of a 1080p
// frame's write time; level 1 takes under half as long for a file about a quarter larger:
// docs/output.md). Throws std::runtime_error naming path and what.
void writePng(const std::string& path, int w, int h, int channels, const uint8_t* codes,
              const char* what);

}  // namespace kiln
