// Reading images into the working space (linear Rec.709, D65): environment maps, reference renders.
// Through the image module (OpenImageIO); exr_rgb_input.h reads plain RGB EXRs without it.
#pragma once

#include <OpenImageIO/oiioversion.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "color/srgb_decode.h"
#include "color/texel_conversion.h"
#include "renderer/core/math.h"

OIIO_NAMESPACE_BEGIN
class ImageSpec;
OIIO_NAMESPACE_END

namespace kiln {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<Color> pixels;  // row-major, top row first
};

// The header facts a loader checks before reading pixels.
struct ImageHeader {
    int width = 0, height = 0, channels = 0;
};

// What failed and why; what() is "FILE: REASON".
struct ImageReadError : std::runtime_error {
    ImageReadError(const std::string& file, const std::string& reason)
        : std::runtime_error(file + ": " + reason), reason(reason) {}
    std::string reason;
};

// Whether an image's texels are sRGB-encoded: 8-bit, or stated sRGB (PNG, JPEG); else linear.
bool isSrgbEncoded(const OIIO::ImageSpec& spec);

// How a colour image with this header reaches the working space: decoded when sRGB-encoded, else
// from its EXR chromaticities (or linear Rec.709 when it states none) by a matrix.
TexelConversion colourConversion(const OIIO::ImageSpec& spec);

// Throws ImageReadError when the file cannot be opened.
ImageHeader readImageHeader(const std::string& path);

// The first three channels converted to the working space from what the file states: EXR
// chromaticities (e.g. a D50 white), or an sRGB-encoded 8-bit image; without either the file is
// taken as linear Rec.709. Throws ImageReadError.
RgbImage readWorkingSpaceImage(const std::string& path);

// Every channel of an image as float, with the channel names, for files kiln wrote itself
// (cached references). Returns false when the file is missing or unreadable.
struct ChannelImage {
    int width = 0, height = 0;
    std::vector<std::string> channelNames;
    std::vector<float> values;                   // width * height * channels, interleaved
    int channel(const std::string& name) const;  // -1 when absent
};
bool readChannelImage(const std::string& path, ChannelImage& image);

}  // namespace kiln
