// The media of a scene as the path tracer meets them: which mesh bounds which medium, which
// boundaries are index-matched (the ray passes straight through; every boundary but a
// dielectric's), and the transmittance a shadow ray collects through them. A path knows the medium
// it is in (-1: none); crossing a closed boundary mesh outwards leaves the medium, inwards enters
// it (media do not nest). Outwards is the way the winding normals point, or against it for a mesh
// wound inside out (its signed volume is negative).
#pragma once

#include <vector>

#include "integrators/medium.h"
#include "renderer/accel/accelerator.h"
#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

struct SurfaceInteraction;

class SceneMedia {
  public:
    explicit SceneMedia(const Scene& scene);
    bool any() const { return !media_.empty(); }
    const HomogeneousMedium& medium(int i) const { return media_[size_t(i)]; }
    // The medium inside the mesh a hit is on, or -1 (spheres, instances, meshes without one).
    int interiorOf(const Hit& hit) const {
        if (hit.shape == kSphereShape || hit.instance != kInvalidId) return -1;
        return hit.shape < interior_.size() ? interior_[hit.shape] : -1;
    }
    // A boundary rays pass straight through, changing only the medium they are in.
    bool indexMatched(const Hit& hit, uint32_t material) const {
        return interiorOf(hit) >= 0 && !dielectric_[material];
    }
    // The medium on the far side of the hit's surface for a ray that arrived on its front (the
    // side its winding normal points to) or back.
    int beyond(const Hit& hit, bool frontFace) const {
        int inside = interiorOf(hit);
        return inside >= 0 && frontFace != bool(inward_[hit.shape]) ? inside : -1;
    }
    // The medium on the far side of a vertex's surface from the arriving ray's, where the path is
    // in `medium` (a surface bounding no medium, or a scattering point, leaves it unchanged).
    int across(const SurfaceInteraction& si, int medium) const;
    // How much of the light at the shadow ray's end reaches its origin, which lies in `medium`:
    // 0 when a surface other than an index-matched boundary is in the way. rays counts the
    // segments traced.
    Color transmittance(const Accelerator& accel, const Ray& shadow, int medium,
                        uint64_t& rays) const;

  private:
    const Scene& scene_;
    std::vector<HomogeneousMedium> media_;
    std::vector<int> interior_;        // per mesh
    std::vector<uint8_t> inward_;      // per mesh: wound inside out
    std::vector<uint8_t> dielectric_;  // per material: a refracting boundary
};

}  // namespace kiln
