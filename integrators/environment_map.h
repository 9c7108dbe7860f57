// A lat-long environment map in memory and its importance-sampling distribution.
#pragma once

#include <vector>

#include "renderer/core/distribution.h"
#include "scene/scene.h"

namespace kiln {

// A lat-long environment map in memory (scaled, in the working space), looked up bilinearly
// (nearest texel for scenes built without the loader), with its importance-sampling distribution.
struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<Color> pixels;
    Color constant{0.0f};  // used when there is no image (uniform environment)
    Distribution2D distribution;
    float scale = 1;
    float rotation = 0;     // radians about +Y (right-handed: counterclockwise seen from above)
    bool bilinear = false;  // between texel centres (the loader's maps); else nearest texel
    Color lookup(const Vec3& dir) const;
    Color bilinearLookup(float u, float v) const;  // (u, v) in [0,1)^2
    Vec3 direction(float u, float v) const;        // (u, v) in [0,1)^2 -> unit direction
    void coordinates(const Vec3& dir, float& u, float& v) const;
};

// The light's map in memory: scaled, non-finite and negative texels zeroed, with its distribution
// (a uniform environment when the light has no image).
EnvironmentMap loadEnvironment(const Light& l);

}  // namespace kiln
