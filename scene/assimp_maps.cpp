// What an Assimp material says about maps beyond its colour: the tangent-space normal map (glTF
// normalTexture with its scale, OBJ norm), alpha (glTF alphaMode MASK/BLEND with alphaCutoff,
// baseColorFactor alpha times the base-colour texture's alpha; OBJ d and map_d as coverage) and
// each texture's UV transform (KHR_texture_transform).
#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <cmath>

#include "scene/importers.h"

namespace kiln {
namespace {

bool isGltf(const std::string& path) {
    std::string ext = lowerExtension(path);
    return ext == ".gltf" || ext == ".glb";
}

void warn(Scene& scene, const Material& m, const std::string& what) {
    scene.warnings.push_back(
        (m.name.empty() ? "an unnamed material" : "material '" + m.name + "'") + ": " + what);
}

// The slot's texture as a raw-data (or colour) source of the scene, with its UV transform; -1
// (and a warning) when it cannot be used.
int mapSource(const aiScene* as, const aiMaterial* am, aiTextureType slot,
              const std::string& assetPath, TextureEncoding encoding, const char* what,
              UvTransform& uv, Material& m, Scene& scene, unsigned index = 0) {
    aiString ref;
    unsigned uvIndex = 0;
    if (am->GetTexture(slot, index, &ref, nullptr, &uvIndex) != AI_SUCCESS) return -1;
    TextureSource source;
    source.encoding = encoding;
    std::string reason;
    if (!assimpTextureSource(as, assetPath, ref.C_Str(), source, reason)) {
        warn(scene, m, reason + "; its " + what + " is dropped");
        return -1;
    }
    if (uvIndex != 0)
        warn(scene, m,
             std::string(what) + " uses UV set " + std::to_string(uvIndex) +
                 "; kiln reads UV set 0");
    readUvTransform(am, slot, assetPath, uv);
    return addTextureSource(scene, std::move(source));
}

void readNormalMap(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                   Material& m, Scene& scene) {
    MaterialMaps& maps = m.maps;
    for (aiTextureType slot : {aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA}) {
        if (am->GetTextureCount(slot) == 0) continue;
        maps.normalTexture = mapSource(as, am, slot, assetPath, TextureEncoding::Data, "normal map",
                                       maps.normalUv, m, scene);
        float scale = 1.0f;
        if (am->Get(AI_MATKEY_GLTF_TEXTURE_SCALE(slot, 0), scale) == AI_SUCCESS &&
            std::isfinite(scale))
            maps.normalScale = scale;
        return;
    }
}

// Principled materials: glTF's metallicRoughnessTexture (Assimp 5.2 stores it in the UNKNOWN slot,
// AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE, and repeats it as METALNESS and
// DIFFUSE_ROUGHNESS): B metallic, G roughness. Other formats (FBX, OBJ map_Pm/map_Pr): a grey
// metalness and a grey roughness map.
void readMetallicRoughness(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                           Material& m, Scene& scene) {
    MaterialMaps& maps = m.maps;
    if (m.kind != MaterialKind::Principled) return;
    if (isGltf(assetPath)) {
        if (am->GetTextureCount(aiTextureType_UNKNOWN) == 0) return;
        int id = mapSource(as, am, aiTextureType_UNKNOWN, assetPath, TextureEncoding::Data,
                           "metallic-roughness texture", maps.metallicUv, m, scene);
        maps.metallicTexture = maps.roughnessTexture = id;
        maps.metallicChannel = 2, maps.roughnessChannel = 1;
        maps.roughnessUv = maps.metallicUv;
        return;
    }
    if (am->GetTextureCount(aiTextureType_METALNESS) > 0) {
        maps.metallicTexture =
            mapSource(as, am, aiTextureType_METALNESS, assetPath, TextureEncoding::Data,
                      "metalness map", maps.metallicUv, m, scene);
        maps.metallicChannel = 0;
    }
    if (am->GetTextureCount(aiTextureType_DIFFUSE_ROUGHNESS) > 0) {
        maps.roughnessTexture =
            mapSource(as, am, aiTextureType_DIFFUSE_ROUGHNESS, assetPath, TextureEncoding::Data,
                      "roughness map", maps.roughnessUv, m, scene);
        maps.roughnessChannel = 0;
    }
}

// The emissive texture (glTF emissiveTexture, OBJ map_Ke, FBX emissive or emission-colour maps),
// sRGB colour multiplying the emissive factor; with no emissive colour it could add nothing.
void readEmissionMap(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                     Material& m, Scene& scene) {
    for (aiTextureType slot : {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR}) {
        if (am->GetTextureCount(slot) == 0) continue;
        if (!(maxComponent(m.emission) > 0)) {
            aiString ref;
            am->GetTexture(slot, 0, &ref);
            warn(scene, m,
                 "emissive map '" + std::string(ref.C_Str()) +
                     "' ignored: the emissive colour it multiplies is black");
            return;
        }
        m.maps.emissionTexture = mapSource(as, am, slot, assetPath, TextureEncoding::Color,
                                           "emissive map", m.maps.emissionUv, m, scene);
        aiString used, other;
        am->GetTexture(slot, 0, &used);
        if (slot == aiTextureType_EMISSIVE &&
            am->GetTexture(aiTextureType_EMISSION_COLOR, 0, &other) == AI_SUCCESS &&
            std::string(other.C_Str()) != used.C_Str())
            warn(scene, m,
                 "emission-colour map '" + std::string(other.C_Str()) +
                     "' ignored: the emissive map is used");
        return;
    }
}

// A path tracer computes occlusion itself: an occlusion map (glTF occlusionTexture, which Assimp
// 5.2 stores in the LIGHTMAP slot; FBX ambient occlusion) is named once per material.
void warnOcclusionMap(const aiMaterial* am, const std::string& assetPath, const Material& m,
                      Scene& scene) {
    for (aiTextureType slot : {aiTextureType_AMBIENT_OCCLUSION, aiTextureType_LIGHTMAP}) {
        if (slot == aiTextureType_LIGHTMAP && !isGltf(assetPath)) continue;
        aiString ref;
        if (am->GetTexture(slot, 0, &ref) != AI_SUCCESS) continue;
        warn(
            scene, m,
            "occlusionTexture '" + std::string(ref.C_Str()) + "' ignored: kiln computes occlusion");
        return;
    }
}

// glTF: alphaMode decides; OPAQUE ignores alpha altogether (the specification's rule).
void readGltfAlpha(const aiMaterial* am, Material& m, Scene& scene) {
    MaterialMaps& maps = m.maps;
    aiString mode;
    if (am->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) != AI_SUCCESS) return;
    std::string name = mode.C_Str();
    if (name == "MASK")
        maps.alphaMode = AlphaMode::Mask;
    else if (name == "BLEND")
        maps.alphaMode = AlphaMode::Blend;
    else if (name != "OPAQUE")
        warn(scene, m, "unknown alphaMode '" + name + "' rendered opaque");
    if (!maps.hasAlpha()) return;
    float opacity = 1.0f, cutoff = 0.5f;
    if (am->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && std::isfinite(opacity))
        maps.opacity = std::clamp(opacity, 0.0f, 1.0f);
    if (am->Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS && std::isfinite(cutoff))
        maps.alphaCutoff = cutoff;
    if (m.albedoTexture >= 0) {
        maps.opacityTexture = m.albedoTexture;
        maps.opacityChannel = 3;
        maps.opacityUv = maps.albedoUv;
    }
}

// OBJ d (dissolve) and map_d, FBX opacity: coverage, the surface stops that fraction of rays.
void readOpacityAlpha(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                      Material& m, Scene& scene) {
    MaterialMaps& maps = m.maps;
    float opacity = 1.0f;
    if (am->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && std::isfinite(opacity) && opacity < 1)
        maps.opacity = std::clamp(opacity, 0.0f, 1.0f);
    if (am->GetTextureCount(aiTextureType_OPACITY) > 0) {
        maps.opacityTexture =
            mapSource(as, am, aiTextureType_OPACITY, assetPath, TextureEncoding::Data,
                      "opacity map", maps.opacityUv, m, scene);
        maps.opacityChannel = 0;
    }
    if (maps.opacity < 1 || maps.opacityTexture >= 0) maps.alphaMode = AlphaMode::Blend;
}

// glTF KHR_materials_clearcoat's textures (Assimp's CLEARCOAT slot: 0 the weight, read from R; 1
// the roughness, from G; 2 the coat's normal map, which kiln does not read: the coat shares the
// surface's normal). The UV transform is slot 0's for both.
// Whether the material states a texture at this index of the slot (Assimp fills the indices below a
// stated one with empty names).
bool statesTexture(const aiMaterial* am, aiTextureType slot, unsigned index, aiString& ref) {
    return am->GetTexture(slot, index, &ref) == AI_SUCCESS && ref.length > 0;
}

void readClearcoatMaps(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                       Material& m, Scene& scene) {
    if (m.kind != MaterialKind::Principled || !isGltf(assetPath)) return;
    MaterialMaps& maps = m.maps;
    auto stated = [&](unsigned index, aiString& ref) {
        return statesTexture(am, aiTextureType_CLEARCOAT, index, ref);
    };
    aiString ref;
    if (stated(0, ref)) {
        maps.clearcoatTexture =
            mapSource(as, am, aiTextureType_CLEARCOAT, assetPath, TextureEncoding::Data,
                      "clearcoat texture", maps.clearcoatUv, m, scene, 0);
        maps.clearcoatChannel = 0;
    }
    if (stated(1, ref)) {
        maps.clearcoatRoughnessTexture =
            mapSource(as, am, aiTextureType_CLEARCOAT, assetPath, TextureEncoding::Data,
                      "clearcoat roughness texture", maps.clearcoatRoughnessUv, m, scene, 1);
        maps.clearcoatRoughnessChannel = 1;
    }
    if (stated(2, ref))
        warn(scene, m,
             "clearcoat normal map '" + std::string(ref.C_Str()) +
                 "' ignored: the coat takes the surface's normal");
}

// glTF KHR_materials_transmission's and _sheen's textures as Assimp 5.2 hands them over: the
// TRANSMISSION slot's 0 (transmissionTexture, R) and 1 (KHR_materials_volume thicknessTexture,
// G: kiln reads thickness only as thin or not, so it is named and ignored); the SHEEN slot's 0
// (sheenColorTexture, an sRGB colour map) and 1 (sheenRoughnessTexture, A).
void readLayerMaps(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                   Material& m, Scene& scene) {
    if (m.kind != MaterialKind::Principled || !isGltf(assetPath)) return;
    MaterialMaps& maps = m.maps;
    aiString ref;
    if (statesTexture(am, aiTextureType_TRANSMISSION, 0, ref)) {
        maps.transmissionTexture =
            mapSource(as, am, aiTextureType_TRANSMISSION, assetPath, TextureEncoding::Data,
                      "transmission texture", maps.transmissionUv, m, scene, 0);
        maps.transmissionChannel = 0;
    }
    if (statesTexture(am, aiTextureType_TRANSMISSION, 1, ref))
        warn(scene, m,
             "KHR_materials_volume thicknessTexture '" + std::string(ref.C_Str()) +
                 "' ignored: kiln reads the thickness factor only (thin or not)");
    if (statesTexture(am, aiTextureType_SHEEN, 0, ref))
        maps.sheenColorTexture =
            mapSource(as, am, aiTextureType_SHEEN, assetPath, TextureEncoding::Color,
                      "sheen colour texture", maps.sheenColorUv, m, scene, 0);
    if (statesTexture(am, aiTextureType_SHEEN, 1, ref)) {
        maps.sheenRoughnessTexture =
            mapSource(as, am, aiTextureType_SHEEN, assetPath, TextureEncoding::Data,
                      "sheen roughness texture", maps.sheenRoughnessUv, m, scene, 1);
        maps.sheenRoughnessChannel = 3;
    }
}

}  // namespace

namespace {

// Assimp's mapping mode (glTF sampler wrapS/wrapT; OBJ -clamp) of the slot's texture on one axis.
TextureWrap readWrap(const aiMaterial* am, const char* key, unsigned slot) {
    int mode = aiTextureMapMode_Wrap;
    if (am->Get(key, slot, 0, mode) != AI_SUCCESS) return TextureWrap::Repeat;
    switch (mode) {
        case aiTextureMapMode_Clamp:
            return TextureWrap::Clamp;
        case aiTextureMapMode_Mirror:
            return TextureWrap::Mirror;
        case aiTextureMapMode_Decal:
            return TextureWrap::Black;
        default:
            return TextureWrap::Repeat;
    }
}

}  // namespace

bool readUvTransform(const aiMaterial* am, unsigned slot, const std::string& assetPath,
                     UvTransform& uv) {
    uv.wrap = {readWrap(am, _AI_MATKEY_MAPPINGMODE_U_BASE, slot),
               readWrap(am, _AI_MATKEY_MAPPINGMODE_V_BASE, slot)};
    const WrapModes wrap = uv.wrap;  // the transforms below replace uv whole
    aiUVTransform x;
    if (am->Get(AI_MATKEY_UVTRANSFORM(slot, 0), x) != AI_SUCCESS) return false;
    if (!isGltf(assetPath)) {
        uv = UvTransform::assimp(x.mTranslation.x, x.mTranslation.y, x.mRotation, x.mScaling.x,
                                 x.mScaling.y);
        uv.wrap = wrap;
        return true;
    }
    // Assimp's glTF importer re-expresses KHR_texture_transform for its own UV-transform rule
    // (rotation negated, the offset moved); undone here, so the extension's exact formula
    // applies (Assimp's rule scales after rotating, which differs for unequal scales).
    float rotation = -x.mRotation, su = x.mScaling.x, sv = x.mScaling.y;
    float c = std::cos(rotation), s = std::sin(rotation);
    float offsetU = x.mTranslation.x - 0.5f * su * (-c + s + 1);
    float offsetV = -(x.mTranslation.y - 0.5f * sv * (s + c - 1) - 1 + sv);
    uv = UvTransform::gltf(offsetU, offsetV, rotation, su, sv);
    uv.wrap = wrap;
    return true;
}

void readAssimpMaps(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                    Material& m, Scene& scene) {
    readNormalMap(as, am, assetPath, m, scene);
    readMetallicRoughness(as, am, assetPath, m, scene);
    readEmissionMap(as, am, assetPath, m, scene);
    warnOcclusionMap(am, assetPath, m, scene);
    if (isGltf(assetPath))
        readGltfAlpha(am, m, scene);
    else if (std::string ext = lowerExtension(assetPath); ext == ".obj" || ext == ".fbx")
        readOpacityAlpha(as, am, assetPath, m, scene);
    readClearcoatMaps(as, am, assetPath, m, scene);
    readLayerMaps(as, am, assetPath, m, scene);
}

bool readsTextureSlot(unsigned slot, const Material& m, const std::string& assetPath) {
    bool principled = m.kind == MaterialKind::Principled;
    switch (slot) {
        case aiTextureType_METALNESS:
        case aiTextureType_DIFFUSE_ROUGHNESS:
            return principled;
        case aiTextureType_UNKNOWN:
        case aiTextureType_CLEARCOAT:
        case aiTextureType_TRANSMISSION:
        case aiTextureType_SHEEN:
            return principled && isGltf(assetPath);
        case aiTextureType_LIGHTMAP:
            return isGltf(assetPath);  // glTF's occlusionTexture: warnOcclusionMap names it
        default:
            return false;
    }
}

}  // namespace kiln
