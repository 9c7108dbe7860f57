// Subsurface scattering by random walk (Chiang, Kutz and Burley 2016, "Practical and Controllable
// Subsurface Scattering for Production Path Tracing", Cycles' method): light that enters a closed
// mesh below its specular layer walks through a homogeneous, isotropic medium whose coefficients
// are set so that a thick slab reflects the surface's albedo with the given mean free path, until
// it reaches the surface again; it leaves there by a Lambertian exit (next-event estimation at the
// exit point, as Cycles).
#pragma once

#include "integrators/medium.h"
#include "renderer/accel/accelerator.h"
#include "renderer/core/sampler.h"
#include "renderer/geometry/interaction.h"
#include "scene/scene.h"

namespace kiln {

// The walk's medium for a multiple-scattering albedo and a mean free path per channel, with the
// throughput factor that goes with it (below a single-scattering albedo of 0.2 Cycles raises the
// albedo to 0.2 and scales the throughput down by as much, so very dark albedos do not need walks
// of hundreds of steps).
struct WalkMedium {
    HomogeneousMedium medium;
    Color weight{1.0f};
};
// Chiang et al.'s fit: single-scattering albedo alpha = 1 - exp(-5.09406 A + 2.61188 A^2 -
// 4.31805 A^3), sigma_t = 1 / (d (1.9 - A + 3.5 (A - 0.8)^2)).
WalkMedium walkMedium(const Color& albedo, const Color& meanFreePath);

// Where a walk left the mesh: the exit point, its normal facing out of the mesh, and the walk's
// throughput.
struct WalkExit {
    SurfaceInteraction si;  // ng, ns face outwards (the side the light leaves to)
    Color weight{1.0f};
};

// A walk from the surface point `entry` (si.ng facing the side the path came from) into the mesh:
// a cosine-distributed direction inwards, then free flights and isotropic scattering. pathBeta
// steers the choice of the colour channel. False when the walk ends inside (absorbed, or lost).
bool randomWalk(const Scene& scene, const Accelerator& accel, const SurfaceInteraction& entry,
                const WalkMedium& walk, const Color& pathBeta, Sampler& sampler, WalkExit& exit,
                uint64_t& rays);

}  // namespace kiln
