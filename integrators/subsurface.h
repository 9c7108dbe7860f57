// Subsurface scattering by random walk (Chiang, Kutz and Burley 2016, "Practical and Controllable
// Subsurface Scattering for Production Path Tracing", Cycles' method): light that enters a closed
// mesh below its specular layer walks through a homogeneous, isotropic medium whose coefficients
// are set so that a thick slab reflects the surface's albedo with the given mean free path, until
// it reaches the surface again (no reflection at the boundary from inside); it leaves there by a
// Lambertian exit (next-event estimation at the exit point, as Cycles).
#pragma once

#include "integrators/medium.h"
#include "renderer/accel/accelerator.h"
#include "renderer/core/sampler.h"
#include "renderer/geometry/interaction.h"
#include "scene/scene.h"

namespace kiln {

// The walk's medium for a multiple-scattering albedo A and a mean free path d per channel, with the
// throughput factor that goes with it. The single-scattering albedo is the one whose semi-infinite
// medium reflects A under this walk's conventions (integrators/slab_albedo.h); the extinction is
// Chiang et al.'s 1 / (d s(A)), s(A) = 1.9 - A + 3.5 (A - 0.8)^2. Below a single-scattering albedo
// of 0.2 the medium is that of 0.2 (Cycles' floor, so very dark albedos need no long walks) and the
// throughput scales what it reflects down to A.
struct WalkMedium {
    HomogeneousMedium medium;
    Color weight{1.0f};
};
WalkMedium walkMedium(const Color& albedo, const Color& meanFreePath);

// Where a walk left the mesh: the exit point, its normal facing out of the mesh, and the walk's
// throughput.
struct WalkExit {
    SurfaceInteraction si;  // ng, ns face outwards (the side the light leaves to)
    Color weight{1.0f};
};

// A walk from the surface point `entry` (si.ng facing the side the path came from) into the mesh:
// a cosine-distributed direction inwards, then free flights and isotropic scattering until a flight
// reaches the surface. pathBeta steers the choice of the colour channel. False when the walk ends
// inside (absorbed, or lost: through a hole in the mesh or after too many steps).
bool randomWalk(const Scene& scene, const Accelerator& accel, const SurfaceInteraction& entry,
                const WalkMedium& walk, const Color& pathBeta, Sampler& sampler, WalkExit& exit,
                uint64_t& rays);

}  // namespace kiln
