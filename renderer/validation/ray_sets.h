// The ray distributions used to compare and benchmark accelerators: camera rays, uniformly random
// rays through the scene bounds, secondary rays leaving surface points, and shadow rays towards
// lights.
#pragma once

#include <string>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "scene/scene.h"

namespace kiln {

enum class RaySetKind { Camera, Random, Secondary, Shadow };
const char* toString(RaySetKind kind);

// Camera rays in the order a renderer traces them: 4x4 pixel blocks (coherent packets) spread
// evenly over a width x height image, until `count` rays.
std::vector<Ray> makeCoherentCameraRays(const Scene& scene, int width, int height, size_t count);

// Deterministic for a given seed. Secondary and shadow rays start at points found with `finder`.
std::vector<Ray> makeRaySet(RaySetKind kind, const Scene& scene, const Accelerator& finder,
                            size_t count, uint64_t seed);

}  // namespace kiln
