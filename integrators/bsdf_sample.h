// One direction a BSDF sampled, with its value and density: what every BSDF's sample() returns;
// and the reflections the BSDF classes share, in the local shading frame (z = the normal).
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

// The mirror direction of wo about the normal (0, 0, 1).
inline Vec3 reflectLocal(const Vec3& wo) { return {-wo.x, -wo.y, wo.z}; }
// w reflected about the unit vector n (a microfacet's half vector).
inline Vec3 reflectAbout(const Vec3& w, const Vec3& n) { return n * (2 * dot(w, n)) - w; }

}  // namespace kiln
