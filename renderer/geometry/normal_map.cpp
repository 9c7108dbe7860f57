#include "renderer/geometry/normal_map.h"

#include <cmath>

#include "renderer/geometry/material_lookup.h"

namespace kiln {
namespace {

// Least cosine between the bent normal and the direction to the viewer.
constexpr float kMinViewCosine = 0.01f;

Vec3 interpolate3(const std::vector<float>& a, size_t stride, const uint32_t* idx, const Vec3& b) {
    auto at = [&](uint32_t i) {
        const float* p = &a[stride * size_t(i)];
        return Vec3(p[0], p[1], p[2]);
    };
    return at(idx[0]) * b.x + at(idx[1]) * b.y + at(idx[2]) * b.z;
}

}  // namespace

void applyNormalMap(const Scene& scene, const Material& material, const Hit& hit,
                    const Vec3& woWorld, float worldWidth, SurfaceInteraction& si) {
    Vec3 m;
    if (!normalMapAt(scene, material, hit, worldWidth, m)) return;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    if (m.x == 0 && m.y == 0 && m.z > 0) return;  // the map says: the normal as it is

    // The tangent frame in world space, around the stored (file-oriented) shading normal.
    const uint32_t* idx = &mesh.indices[3 * size_t(hit.prim)];
    Vec3 bary(1 - hit.u - hit.v, hit.u, hit.v);
    Vec3 t = interpolate3(mesh.tangents, 4, idx, bary);
    float handedness = mesh.tangents[4 * size_t(idx[0]) + 3];
    if (hit.instance != kInvalidId) t = scene.instances[hit.instance].objectToWorld.vector(t);
    Vec3 n = si.nsStored;
    t = t - n * dot(n, t);
    if (!(dot(t, t) > 0)) return;
    t = normalize(t);
    Vec3 b = cross(n, t) * handedness;
    Vec3 bent = normalize(t * m.x + b * m.y + n * m.z);
    if (!isFinite(bent)) return;

    // Face it like the unmapped normal (towards the geometric normal's side when that one was).
    bool flipped = dot(si.ns, si.nsStored) < 0;
    Vec3 ns = flipped ? -bent : bent;
    float c = dot(ns, woWorld);
    if (c < kMinViewCosine) ns = normalize(ns + woWorld * (kMinViewCosine - c));
    si.ns = ns;
    si.nsStored = flipped ? -ns : ns;
}

}  // namespace kiln
