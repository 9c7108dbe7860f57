// OpenImageIO 2.4's EXR writer stores no `oiio:ColorSpace` (and its reader then reports "Linear"
// for every EXR, so `oiiotool --ociodisplay` fails with a config that has no colour space of that
// name). kiln adds the attribute itself: the file OpenImageIO wrote is copied with its compressed
// pixel blocks as they are (OpenEXR's copyPixels: no decoding, no recompression) under a header
// that also names the colour space; OpenImageIO's reader then reports it.
#pragma once

#include <string>

namespace kiln {

// Writes `to` as the single-part scanline EXR `from` with the string attribute oiio:ColorSpace
// set to `colourSpace`. Throws std::runtime_error naming `from`.
void stampExrColourSpace(const std::string& from, const std::string& to,
                         const std::string& colourSpace);

}  // namespace kiln
