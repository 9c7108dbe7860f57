// Rays and what traversal reports about a hit.
#pragma once

#include <cstdint>

#include "renderer/core/math.h"

namespace kiln {

struct Ray {
    Vec3 origin;
    float tMin = 0.0f;
    Vec3 dir;  // not necessarily unit length
    float tMax = kInfinity;
};

constexpr uint32_t kInvalidId = 0xffffffffu;
constexpr uint32_t kSphereShape =
    0xfffffffeu;  // Hit::shape for analytic spheres (prim = sphere index)

// Only what traversal knows. shape is a mesh index or kSphereShape; instance indexes
// Scene::instances or is kInvalidId for geometry placed directly in world space.
struct Hit {
    float t = kInfinity;
    float u = 0, v = 0;  // barycentrics of vertices 1 and 2 (triangles)
    uint32_t shape = kInvalidId;
    uint32_t prim = kInvalidId;
    uint32_t instance = kInvalidId;
    bool valid() const { return shape != kInvalidId; }
};

}  // namespace kiln
