// The space kiln renders in: the OCIO config's scene_linear, whatever its primaries (linear
// Rec.709 in kiln's own config, ACEScg in studio ones). Colours that files give as linear Rec.709
// are converted into it by one 3x3 matrix, found through the config's interchange role once per
// config; when scene_linear is linear Rec.709 nothing is converted (images stay bit-identical).
#pragma once

#include <string>

#include "color/chromaticities.h"
#include "renderer/core/math.h"

namespace kiln {

struct WorkingSpace {
    std::string name;    // the scene_linear colour space
    bool known = false;  // an interchange role (aces_interchange, cie_xyz_d65_interchange) told
                         // its primaries; without one it is taken as linear Rec.709
    bool rec709 = true;  // linear Rec.709 / D65 (within 2e-3 in XYZ): no conversion
    Mat3 fromRec709 = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    Chromaticities chromaticities = kRec709D65;
    double offFromRec709 = 0;  // the largest XYZ difference of its primaries from Rec.709's
};

// The working space of the config kiln follows now (color_config.h), made once per read of the
// config (ocioConfigStamp: a config edited or read in another environment is described again).
// Throws std::invalid_argument naming the config when it cannot be loaded.
const WorkingSpace& workingSpace();

// Linear Rec.709 -> the working space (identity when it is Rec.709).
Color fromRec709(const WorkingSpace& space, const Color& c);

}  // namespace kiln
