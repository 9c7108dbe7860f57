// Assimp's metallic-roughness keys (glTF 2.0 and its KHR_materials_clearcoat, _transmission,
// _volume, _sheen and _ior; OBJ's Pm/Pr and any format where Assimp states a metallic factor) as
// kiln's principled material (docs/import.md lists what maps to what).
#include <assimp/material.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "scene/importers.h"

namespace kiln {

namespace {

// KHR_materials_transmission, _volume and _sheen as Assimp 5.2 hands them over.
void readPrincipledLayers(
    const aiMaterial* am, Material& m,
    const std::function<bool(const char*, unsigned, unsigned, float&)>& factor) {
    if (factor(AI_MATKEY_TRANSMISSION_FACTOR, m.transmission))
        m.transmission = std::clamp(m.transmission, 0.0f, 1.0f);
    if (factor(AI_MATKEY_VOLUME_THICKNESS_FACTOR, m.thickness))
        m.thickness = std::max(0.0f, m.thickness);
    float distance = 0;
    if (factor(AI_MATKEY_VOLUME_ATTENUATION_DISTANCE, distance) && distance > 0)
        m.attenuationDistance = distance;
    aiColor3D c;
    if (am->Get(AI_MATKEY_VOLUME_ATTENUATION_COLOR, c) == AI_SUCCESS)
        m.attenuationColor = max(Color(c.r, c.g, c.b), Color(0.0f));
    // glTF's sheen is on where its colour is not black (weight 1, roughness 0 by default).
    if (am->Get(AI_MATKEY_SHEEN_COLOR_FACTOR, c) == AI_SUCCESS) {
        m.sheenColor = max(Color(c.r, c.g, c.b), Color(0.0f));
        m.sheen = maxComponent(m.sheenColor) > 0 ? 1.0f : 0.0f;
        m.sheenRoughness = 0;
        if (factor(AI_MATKEY_SHEEN_ROUGHNESS_FACTOR, m.sheenRoughness))
            m.sheenRoughness = std::clamp(m.sheenRoughness, 0.0f, 1.0f);
    }
}

}  // namespace

bool statesMetallicRoughness(const aiMaterial* am) {
    aiColor3D base;
    float metallic = 0;
    return am->Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS ||
           (am->Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS && std::isfinite(metallic));
}

bool readPrincipled(const aiMaterial* am, bool gltf, Material& m) {
    // Get() overwrites its argument even when the key is missing: only a success counts.
    auto factor = [&](const char* key, unsigned type, unsigned index, float& out) {
        float v = 0;
        if (am->Get(key, type, index, v) != AI_SUCCESS || !std::isfinite(v)) return false;
        out = v;
        return true;
    };
    if (!statesMetallicRoughness(am)) return false;  // a Phong/Lambert material
    aiColor3D base;
    bool statesBase = am->Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS;
    float metallic = 1.0f;  // glTF's default
    factor(AI_MATKEY_METALLIC_FACTOR, metallic);
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
    m.ior = 1.5f;  // glTF's dielectric: F0 0.04
    // KHR_materials_ior (other formats' refraction indices, OBJ Ni above all, are often 1 or
    // junk: a principled material from them keeps glTF's 1.5).
    float ior = 0;
    if (gltf && factor(AI_MATKEY_REFRACTI, ior) && ior >= 1) m.ior = ior;
    readPrincipledLayers(am, m, factor);
    return true;
}

bool readPhongSpecular(const aiMaterial* am, PhongDialect dialect, Material& m) {
    aiColor3D ks;
    if (dialect == PhongDialect::None || am->Get(AI_MATKEY_COLOR_SPECULAR, ks) != AI_SUCCESS)
        return false;
    const Color tint = max(Color(ks.r, ks.g, ks.b), Color(0.0f));
    const float mean = (tint.x + tint.y + tint.z) / 3;
    if (!std::isfinite(mean) || mean <= 0) return false;
    float blenderSpecular = mean, shininess = 0, specularFactor = 0.25f;  // FBX's default
    const bool statesShininess = am->Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS &&
                                 std::isfinite(shininess) && shininess >= 0;
    float roughness = 0.5f;  // Blender's default where the file states none
    if (dialect == PhongDialect::Obj) {
        if (statesShininess) roughness = 1 - std::sqrt(std::min(shininess, 1000.0f) / 1000);
    } else {
        if (am->Get(AI_MATKEY_SHININESS_STRENGTH, specularFactor) != AI_SUCCESS ||
            !std::isfinite(specularFactor))
            specularFactor = 0.25f;
        blenderSpecular = 2 * std::max(0.0f, specularFactor);
        if (!statesShininess) shininess = 20;  // FBX's default
        roughness = 1 - std::sqrt(std::min(shininess, 100.0f) / 100);
    }
    m.kind = MaterialKind::Principled;  // base colour: the diffuse colour already read
    m.metallic = 0;
    m.roughness = std::clamp(roughness, 0.0f, 1.0f);
    m.ior = 1.5f;
    m.specular = 2 * blenderSpecular;  // F0 = 0.04 specular colour specular = 0.08 Blender's input
    m.specularColor = tint / mean;
    return true;
}

}  // namespace kiln
