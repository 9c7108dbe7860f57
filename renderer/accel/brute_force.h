// The course's "without a BVH": every ray tested against every primitive, with the same
// triangle and sphere tests as the reference BVH, so BVH-against-none timings compare traversal
// alone. Only for small scenes: a render's cost is rays x primitives.
#pragma once

#include "renderer/accel/accelerator.h"

namespace kiln {

// Nanoseconds one core takes for one ray-primitive test (measured on the shared 2-core machine,
// docs/cs184.md, rounded up): what the refusal of a brute-force render estimates with.
constexpr double kBruteForceNsPerTest = 10.0;

// The primitives a ray is tested against: world triangles, spheres, and each instance's triangles.
uint64_t bruteForcePrimitiveCount(const Scene& scene);

std::unique_ptr<Accelerator> makeBruteForceAccelerator(const Scene& scene);

}  // namespace kiln
