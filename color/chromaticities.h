// Converting RGB with stated chromaticities (an EXR's `chromaticities` attribute) into the working
// space, linear Rec.709 / D65, with Bradford chromatic adaptation of the white point.
#pragma once

#include <array>

#include "renderer/core/math.h"

namespace kiln {

using Mat3 = std::array<std::array<double, 3>, 3>;
// Red, green, blue and white xy, in the OpenEXR attribute's order.
using Chromaticities = std::array<float, 8>;

constexpr Chromaticities kRec709D65 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

bool sameChromaticities(const Chromaticities& a, const Chromaticities& b, float tolerance = 1e-4f);
// RGB in `from` -> linear Rec.709 / D65 (the working space's own matrix: working_space.h).
Mat3 toWorkingSpace(const Chromaticities& from);

Mat3 multiply(const Mat3& a, const Mat3& b);
Mat3 inverse(const Mat3& m);
Color applyMatrix(const Mat3& m, const Color& c);

}  // namespace kiln
