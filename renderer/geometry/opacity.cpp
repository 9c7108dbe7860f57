#include "renderer/geometry/opacity.h"

#include <algorithm>

#include "renderer/core/sampler.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

bool meshHasAlpha(const Scene& scene, uint32_t mesh) {
    for (uint32_t id : scene.meshes[mesh].materialIds)
        if (id < scene.materials.size() && scene.materials[id].maps.hasAlpha()) return true;
    return false;
}

bool sceneHasAlpha(const Scene& scene) {
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        if (meshHasAlpha(scene, m)) return true;
    return false;
}

uint32_t raySeed(const Ray& r) {
    uint64_t h = mix64(std::bit_cast<uint32_t>(r.origin.x) |
                       uint64_t(std::bit_cast<uint32_t>(r.origin.y)) << 32);
    h = mix64(h ^ (std::bit_cast<uint32_t>(r.origin.z) | uint64_t(std::bit_cast<uint32_t>(r.dir.x))
                                                             << 32));
    h = mix64(
        h ^ (std::bit_cast<uint32_t>(r.dir.y) | uint64_t(std::bit_cast<uint32_t>(r.dir.z)) << 32));
    return uint32_t(h);
}

float coverageAt(const Scene& scene, uint32_t mesh, uint32_t prim, float b1, float b2) {
    const TriangleMesh& m = scene.meshes[mesh];
    const Material& material = scene.materials[m.materialOf(prim)];
    if (material.maps.alphaMode == AlphaMode::Opaque) return 1.0f;
    float alpha = alphaAt(scene, material, {mesh, prim, b1, b2});
    if (material.maps.alphaMode == AlphaMode::Mask)
        return alpha >= material.maps.alphaCutoff ? 1.0f : 0.0f;
    return std::clamp(alpha, 0.0f, 1.0f);
}

bool surfaceStopsRay(const Scene& scene, uint32_t mesh, uint32_t prim, float b1, float b2,
                     uint32_t instance, uint32_t seed) {
    const TriangleMesh& m = scene.meshes[mesh];
    const Material& material = scene.materials[m.materialOf(prim)];
    switch (material.maps.alphaMode) {
        case AlphaMode::Opaque:
            return true;
        case AlphaMode::Mask:
            return alphaAt(scene, material, {mesh, prim, b1, b2}) >= material.maps.alphaCutoff;
        case AlphaMode::Blend: {
            uint64_t h = mix64(uint64_t(seed) << 32 ^ uint64_t(mesh) << 20 ^ prim ^
                               uint64_t(instance) * 0x9e3779b97f4a7c15ull);
            float coin = float(h >> 40) * 0x1p-24f;  // uniform in [0, 1)
            return coin < alphaAt(scene, material, {mesh, prim, b1, b2});
        }
    }
    return true;
}

}  // namespace kiln
