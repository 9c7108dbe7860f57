// Alpha at a candidate hit, decided the same way by every accelerator: a glTF MASK material stops
// a ray where alpha >= alphaCutoff, a BLEND material (and OBJ dissolve) stops it with probability
// alpha. Blend's coin is a hash of the world-space ray and the primitive, so a ray always meets the
// same surfaces whatever thread or tile traces it, and both accelerators agree.
#pragma once

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

// Whether any triangle of this mesh has a material with alpha (accelerators install their filter
// only on those).
bool meshHasAlpha(const Scene& scene, uint32_t mesh);
bool sceneHasAlpha(const Scene& scene);

// The coin of a world-space ray: a hash of its origin and direction bits.
uint32_t raySeed(const Ray& worldRay);

// The probability that a ray meeting triangle `prim` of `mesh` at (b1, b2) stops there: 1 opaque,
// 0 or 1 for a mask, alpha for blend (the expectation of surfaceStopsRay's coin). A light sample
// on an emitter weighs its radiance by it, as rays hitting the emitter see it.
float coverageAt(const Scene& scene, uint32_t mesh, uint32_t prim, float b1, float b2);

// Whether a candidate hit on triangle `prim` of `mesh` (placed by `instance`, or kInvalidId)
// stops the ray whose seed is `seed`.
bool surfaceStopsRay(const Scene& scene, uint32_t mesh, uint32_t prim, float b1, float b2,
                     uint32_t instance, uint32_t seed);

}  // namespace kiln
