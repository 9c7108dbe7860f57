// What sampling a light gives: a direction towards it with its radiance and density (next-event
// estimation), or light leaving an emitting surface (a photon).
#pragma once

#include "renderer/geometry/interaction.h"

namespace kiln {

// Light leaving an emitting surface (a photon): where it starts, where it goes, and its power
// (the light's radiance over the densities of the point, the direction and the light's choice).
struct EmissionSample {
    SurfaceInteraction from;
    Vec3 dir;
    Color power;
    bool hittable = false;  // rays can hit the light (LightSet::hittable)
};

// How the scene's lights are prepared for the integrator that samples them.
struct LightSetOptions {
    // Every light sample is weighed by MIS against BSDF sampling that reaches every direction a
    // BSDF reflects light into: an environment map may then be sampled MIS-compensated.
    bool misWithBsdf = false;
};

struct LightSample {
    Color Li;       // radiance arriving at the reference point (before visibility)
    Vec3 wi;        // unit direction towards the light
    Vec3 p;         // point on the light (finite lights)
    Vec3 pError;    // absolute error bound of p
    float pdf = 0;  // solid angle density; 1 for delta lights
    bool delta = false;
    bool infinite = false;  // shadow ray has no end point
};

}  // namespace kiln
