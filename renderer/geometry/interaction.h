// Turns what traversal reports into a shading point, identically for every accelerator, and spawns
// every secondary ray (the one place that offsets ray origins).
#pragma once

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

struct SurfaceInteraction {
    Vec3 p;         // hit point, rebuilt from barycentrics (triangles) or reprojected (spheres)
    Vec3 pError;    // conservative absolute error bound of p per axis
    Vec3 ng;        // geometric normal, unit, facing the side the ray came from
    Vec3 ns;        // shading normal, unit, same hemisphere as ng
    Vec3 nsStored;  // shading normal as the file orients it (normal-shading views show this one)
    // Where rays leave, on the front (ng) and back side: p pushed off by the error bound, computed
    // once here because a vertex spawns -l shadow rays and a continuation from the same two points.
    Vec3 originFront, originBack;
    float t = 0;
    uint32_t material = 0;
    uint32_t shape = kInvalidId, prim = kInvalidId, instance = kInvalidId;
    bool frontFace = true;  // the ray arrived on the side the geometric normal (winding) points to
};

SurfaceInteraction makeInteraction(const Scene& scene, const Ray& ray, const Hit& hit);
// A point no ray found (on a light, leaving it): position, error bound and unit normal, with the
// same spawn origins a hit there would have.
SurfaceInteraction surfacePoint(const Vec3& p, const Vec3& pError, const Vec3& n);

// What makeInteraction will read for a triangle hit, requested ahead from memory: on meshes far
// larger than the caches each hit's indices and vertices are misses. Stage 1 fetches the index
// triple; stage 2 (some hits later, once the indices have arrived) the vertices and normals.
void prefetchHitIndices(const Scene& scene, const Hit& hit);
void prefetchHitVertices(const Scene& scene, const Hit& hit);

// Origin pushed off the surface by the error bound along the normal, on the side of dir.
inline const Vec3& offsetRayOrigin(const SurfaceInteraction& si, const Vec3& dir) {
    return dot(dir, si.ng) < 0 ? si.originBack : si.originFront;
}
Ray spawnRay(const SurfaceInteraction& si, const Vec3& dir);
// A ray to a point (shadow rays): stops short of the target by the target's error bound (and
// Embree's distance error), so the surface the target lies on does not occlude it.
Ray spawnRayTo(const SurfaceInteraction& si, const Vec3& target,
               const Vec3& targetError = Vec3(0.0f));

}  // namespace kiln
