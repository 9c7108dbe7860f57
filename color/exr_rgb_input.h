// An EXR's colour read with OpenEXR alone, so a render lit by an EXR environment map never loads
// the image module (OpenImageIO and the libraries it pulls in: image_module.h).
#pragma once

#include <optional>
#include <string>

#include "color/image_input.h"

namespace kiln {

// The image readWorkingSpaceImage gives, bit for bit, for an EXR whose first three channels in
// OpenImageIO's order are R, G, B of the unlayered part, stored as half or float: the data window
// of part 0 at full resolution, converted to the working space from its chromaticities (or its
// oiio:ColorSpace "sRGB"). std::nullopt for every other file (another format, other channels,
// a subsampled channel, those attributes spelt or typed otherwise, one OpenEXR cannot read, or
// too large for memory): the caller reads it through the image module as before, whose errors
// name the problem.
std::optional<RgbImage> readExrRgb(const std::string& path);

}  // namespace kiln
