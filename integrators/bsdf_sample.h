// One direction a BSDF sampled, with its value and density: what every BSDF's sample() returns.
#pragma once

#include "renderer/core/math.h"

namespace kiln {

struct BsdfSample {
    Color f;        // BSDF value (for delta lobes: the value whose ratio to pdf is the weight)
    Vec3 wi;        // local
    float pdf = 0;  // solid angle; for delta lobes the discrete probability of the lobe
    bool delta = false;
    bool transmission = false;
    // Where > 0, the density MIS weighs this direction by instead of pdf: it must be what pdf()
    // gives light sampling's weights for the same direction (a guided bounce: its cosine part).
    float misPdf = 0;
};

}  // namespace kiln
