// Assimp's metallic-roughness keys (glTF 2.0 and its KHR_materials_emissive_strength, _specular
// and _clearcoat; OBJ's Pm/Pr and any format where Assimp states a metallic factor) as kiln's
// principled material (docs/import.md lists what maps to what).
#include <assimp/material.h>

#include <algorithm>
#include <cmath>

#include "scene/importers.h"

namespace kiln {

bool readPrincipled(const aiMaterial* am, Material& m) {
    // Get() overwrites its argument even when the key is missing: only a success counts.
    auto factor = [&](const char* key, unsigned type, unsigned index, float& out) {
        float v = 0;
        if (am->Get(key, type, index, v) != AI_SUCCESS || !std::isfinite(v)) return false;
        out = v;
        return true;
    };
    aiColor3D base;
    bool statesBase = am->Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS;
    float metallic = 1.0f;  // glTF's default
    bool statesMetallic = factor(AI_MATKEY_METALLIC_FACTOR, metallic);
    if (!statesBase && !statesMetallic) return false;  // a Phong/Lambert material
    m.kind = MaterialKind::Principled;
    if (statesBase) m.albedo = Color(base.r, base.g, base.b);
    m.metallic = std::clamp(metallic, 0.0f, 1.0f);
    m.roughness = 1.0f;  // glTF's default
    if (factor(AI_MATKEY_ROUGHNESS_FACTOR, m.roughness))
        m.roughness = std::clamp(m.roughness, 0.0f, 1.0f);
    if (factor(AI_MATKEY_SPECULAR_FACTOR, m.specular)) m.specular = std::max(0.0f, m.specular);
    if (factor(AI_MATKEY_CLEARCOAT_FACTOR, m.clearcoat))
        m.clearcoat = std::clamp(m.clearcoat, 0.0f, 1.0f);
    if (factor(AI_MATKEY_CLEARCOAT_ROUGHNESS_FACTOR, m.clearcoatRoughness))
        m.clearcoatRoughness = std::clamp(m.clearcoatRoughness, 0.0f, 1.0f);
    m.ior = 1.5f;  // glTF's dielectric: F0 0.04 (KHR_materials_ior is not read)
    return true;
}

}  // namespace kiln
