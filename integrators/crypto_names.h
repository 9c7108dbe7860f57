// The names Cryptomatte hashes: one per object (a mesh drawn by itself, an instance, a sphere) and
// one per material, with a fallback for unnamed ones, and the ids the integrator records.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

struct CryptoNames {
    // Indexed like the scene's meshes, instances ("MESH#K"), spheres and materials.
    std::vector<std::string> meshes, instances, spheres, materials;
    explicit CryptoNames(const Scene& scene);
    // Every object that can be seen (prototype meshes appear through their instances only).
    std::vector<std::string> objects(const Scene& scene) const;
};

// Cryptomatte id bits per object and material, looked up per camera hit.
class CryptoIds {
  public:
    CryptoIds() = default;
    explicit CryptoIds(const Scene& scene);
    uint32_t object(const Hit& hit) const;
    uint32_t material(uint32_t material) const { return materials_[material]; }

  private:
    std::vector<uint32_t> meshes_, instances_, spheres_, materials_;
};

}  // namespace kiln
