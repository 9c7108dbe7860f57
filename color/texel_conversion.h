// How a colour image's texels reach the working space (working_space.h): sRGB-encoded ones are
// decoded by the OCIO config straight into scene_linear (srgb_decode.h); linear ones are in their
// stated chromaticities, else linear Rec.709, and go through one 3x3 matrix. Data images (normals,
// roughness) and linear Rec.709 colour in a Rec.709 working space are left as they are.
#pragma once

#include <cstddef>

#include "color/chromaticities.h"

namespace kiln {

struct TexelConversion {
    bool decodeSrgb = false;
    bool matrix = false;  // toWorking applies
    Mat3 toWorking = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

    bool none() const { return !decodeSrgb && !matrix; }
    // `count` interleaved texels of `channels` floats: the first three are colour; a grey image
    // (fewer than three) only decodes, as a matrix keeps white white.
    void apply(float* texels, size_t count, int channels) const;
};

// A linear image in `stated` chromaticities (null: none stated, taken as linear Rec.709) into the
// working space: no matrix when both are Rec.709.
TexelConversion linearConversion(const Chromaticities* stated);

// A colour image into the working space: decoded when sRGB-encoded, else linearConversion(stated).
TexelConversion imageConversion(bool srgbEncoded, const Chromaticities* stated);

}  // namespace kiln
