// The validation accelerator: our own BVH with Moller-Trumbore triangles and analytic spheres.
#pragma once

#include "renderer/accel/accelerator.h"
#include "renderer/accel/bvh.h"

namespace kiln {

class ReferenceAccelerator final : public Accelerator {
  public:
    ReferenceAccelerator(const Scene& scene, const ReferenceBvhOptions& options);
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    const AcceleratorStats& stats() const override { return stats_; }

    // Same queries, also counting box and primitive tests.
    bool intersect(const Ray& ray, Hit& hit, TraversalCounters& counters) const;
    BvhStatistics topLevelStatistics() const { return top_.statistics(); }

  private:
    // Top-level items: world-space triangles, spheres and instances in one BVH.
    enum class ItemKind : uint32_t { Triangle, Sphere, Instance };
    struct Item {
        ItemKind kind;
        uint32_t a;  // mesh, sphere or instance index
        uint32_t b;  // triangle index (triangles)
    };
    template <bool AnyHit>
    bool trace(Ray& ray, Hit* hit, TraversalCounters* counters) const;
    // `instance` and `seed` (the world ray's, opacity.h) decide alpha on meshes that have it.
    bool testTriangle(const TriangleMesh& mesh, uint32_t tri, Ray& ray, Hit* hit,
                      uint32_t instance, uint32_t seed) const;

    const Scene& scene_;
    std::vector<Item> items_;
    Bvh top_;
    std::vector<Bvh> prototypeBvh_;  // per mesh; empty unless the mesh is instanced
    std::vector<bool> alphaMesh_;    // per mesh: its materials have alpha
    bool hasAlpha_ = false;
    AcceleratorStats stats_;
};

}  // namespace kiln
