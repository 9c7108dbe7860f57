#include "renderer/accel/brute_force.h"

#include <chrono>

#include "renderer/geometry/opacity.h"
#include "renderer/geometry/shapes.h"

namespace kiln {
namespace {

class BruteForceAccelerator final : public Accelerator {
  public:
    explicit BruteForceAccelerator(const Scene& scene) : scene_(scene) {
        auto start = std::chrono::steady_clock::now();
        std::vector<bool> proto = scene.prototypeMask();
        for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
            if (!proto[m]) worldMeshes_.push_back(m);
            alphaMesh_.push_back(meshHasAlpha(scene, m));
        }
        stats_.description = "brute force (every ray against every primitive)";
        stats_.buildSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    bool intersect(const Ray& ray, Hit& hit) const override { return trace<false>(ray, &hit); }
    bool occluded(const Ray& ray) const override { return trace<true>(ray, nullptr); }
    const AcceleratorStats& stats() const override { return stats_; }

  private:
    // Every triangle of mesh in order; a tie in t keeps the earlier (lower) triangle, as Embree
    // and the reference BVH do. Returns whether any was hit (ray.tMax shortened to it).
    template <bool AnyHit>
    bool testMesh(uint32_t mesh, Ray& ray, Hit* hit, uint32_t instance, uint32_t seed) const {
        bool alpha = alphaMesh_[mesh];
        const TriangleMesh& m = scene_.meshes[mesh];
        bool found = false, earlier = hit->valid();
        for (uint32_t tri = 0; tri < m.triangleCount(); ++tri) {
            const uint32_t* idx = &m.indices[3 * size_t(tri)];
            float t, u, v;
            if (!intersectTriangle(ray, m.vertex(idx[0]), m.vertex(idx[1]), m.vertex(idx[2]), t, u,
                                   v) ||
                ((found || earlier) && !(t < ray.tMax)) ||
                (alpha && !surfaceStopsRay(scene_, mesh, tri, u, v, instance, seed)))
                continue;
            if constexpr (AnyHit) return true;
            found = true;
            ray.tMax = t;
            *hit = Hit{t, u, v, mesh, tri, instance};
        }
        return found;
    }

    template <bool AnyHit>
    bool trace(const Ray& original, Hit* out) const {
        Ray ray = original;
        Hit hit;
        uint32_t seed = raySeed(original);
        bool found = false;
        for (uint32_t m : worldMeshes_)
            if (testMesh<AnyHit>(m, ray, &hit, kInvalidId, seed)) {
                if constexpr (AnyHit) return true;
                found = true;
            }
        for (uint32_t s = 0; s < scene_.spheres.size(); ++s) {
            float t;
            if (!intersectSphere(ray, scene_.spheres[s].center, scene_.spheres[s].radius, t))
                continue;
            if constexpr (AnyHit) return true;
            found = true;
            ray.tMax = t;
            hit = Hit{t, 0, 0, kSphereShape, s, kInvalidId};
        }
        for (uint32_t j = 0; j < scene_.instances.size(); ++j) {
            // Object space, same parametrisation: t carries over.
            const Instance& inst = scene_.instances[j];
            Ray local{inst.worldToObject.point(ray.origin), ray.tMin,
                      inst.worldToObject.vector(ray.dir), ray.tMax};
            if (!testMesh<AnyHit>(inst.mesh, local, &hit, j, seed)) continue;
            if constexpr (AnyHit) return true;
            found = true;
            ray.tMax = local.tMax;
        }
        if (found && out) *out = hit;
        return found;
    }

    const Scene& scene_;
    std::vector<uint32_t> worldMeshes_;
    std::vector<bool> alphaMesh_;  // per mesh: its materials have alpha (opacity.h)
    AcceleratorStats stats_;
};

}  // namespace

uint64_t bruteForcePrimitiveCount(const Scene& scene) {
    std::vector<bool> proto = scene.prototypeMask();
    uint64_t n = scene.spheres.size();
    for (size_t m = 0; m < scene.meshes.size(); ++m)
        if (!proto[m]) n += scene.meshes[m].triangleCount();
    for (const Instance& inst : scene.instances) n += scene.meshes[inst.mesh].triangleCount();
    return n;
}

std::unique_ptr<Accelerator> makeBruteForceAccelerator(const Scene& scene) {
    return std::make_unique<BruteForceAccelerator>(scene);
}

}  // namespace kiln
