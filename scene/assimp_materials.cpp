// What kiln takes from an Assimp material beyond its colours: the base-colour texture becomes a
// texture source of the scene (a file relative to the asset, or an image embedded in it: glTF "*N"
// references, data URIs, .glb buffers); every other texture slot and every shading feature kiln
// cannot honour yet (the gloss and specular colour of Phong materials in formats other than OBJ
// and FBX, ...) is named in a warning.
#include <assimp/material.h>
#include <assimp/scene.h>

#include <filesystem>
#include <sstream>

#include "scene/importers.h"

namespace kiln {
namespace {

// Slots whose textures kiln does not apply (yet), with the words a warning uses (emissive and
// occlusion maps: scene/assimp_maps.cpp reads or names them).
constexpr std::pair<aiTextureType, const char*> kIgnoredSlots[] = {
    {aiTextureType_HEIGHT, "height/bump map"},
    {aiTextureType_DISPLACEMENT, "displacement map"},
    {aiTextureType_METALNESS, "metallic map"},
    {aiTextureType_DIFFUSE_ROUGHNESS, "roughness map"},
    {aiTextureType_SPECULAR, "specular map"},
    {aiTextureType_SHININESS, "shininess map"},
    {aiTextureType_AMBIENT, "ambient map"},
    {aiTextureType_LIGHTMAP, "lightmap"},
    {aiTextureType_REFLECTION, "reflection map"},
    {aiTextureType_SHEEN, "sheen map"},                // glTF: read (scene/assimp_maps.cpp)
    {aiTextureType_CLEARCOAT, "clearcoat map"},        // glTF: read
    {aiTextureType_TRANSMISSION, "transmission map"},  // glTF: read
    {aiTextureType_UNKNOWN, "texture of unknown use (glTF metallic-roughness)"},
};

std::string materialLabel(const Material& m) {
    return m.name.empty() ? "an unnamed material" : "material '" + m.name + "'";
}

std::string number(float v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

}  // namespace

// The source an Assimp texture path names, or a reason it cannot be used.
bool assimpTextureSource(const aiScene* as, const std::string& assetPath, const std::string& ref,
                         TextureSource& source, std::string& reason) {
    if (const aiTexture* embedded = as->GetEmbeddedTexture(ref.c_str())) {
        if (embedded->mHeight != 0) {
            reason =
                "embedded texture " + ref + " is uncompressed texels, which kiln does not read";
            return false;
        }
        const auto* begin = reinterpret_cast<const unsigned char*>(embedded->pcData);
        source.bytes =
            std::make_shared<const std::vector<unsigned char>>(begin, begin + embedded->mWidth);
        source.formatHint = embedded->achFormatHint;
        source.name = assetPath + " (embedded " + ref + ")";
        return true;
    }
    if (!ref.empty() && ref[0] == '*') {
        reason = "embedded texture " + ref + " is missing from the file";
        return false;
    }
    std::string path = ref;
    std::replace(path.begin(), path.end(), '\\', '/');  // files written on Windows
    std::filesystem::path p(path);
    if (p.is_relative()) p = std::filesystem::path(assetPath).parent_path() / p;
    source.name = p.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) {
        reason = "texture file " + source.name + " not found";
        return false;
    }
    // Opening a FIFO would block the load until a writer comes.
    if (!std::filesystem::is_regular_file(p, ec)) {
        reason = "texture file " + source.name + " is not a regular file";
        return false;
    }
    return true;
}

// The index of the source in the scene, adding it once per file (materials often share one).
int addTextureSource(Scene& scene, TextureSource&& source) {
    for (size_t i = 0; i < scene.textureSources.size(); ++i) {
        const TextureSource& s = scene.textureSources[i];
        if (!s.bytes && !source.bytes && s.name == source.name && s.encoding == source.encoding)
            return int(i);
    }
    scene.textureSources.push_back(std::move(source));
    return int(scene.textureSources.size()) - 1;
}

namespace {

void readBaseColour(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                    bool statesColour, Material& m, Scene& scene) {
    aiTextureType slot = am->GetTextureCount(aiTextureType_BASE_COLOR) > 0
                             ? aiTextureType_BASE_COLOR
                             : aiTextureType_DIFFUSE;
    aiString ref;
    unsigned uvIndex = 0;
    if (am->GetTexture(slot, 0, &ref, nullptr, &uvIndex) != AI_SUCCESS) return;
    TextureSource source;
    std::string reason;
    if (!assimpTextureSource(as, assetPath, ref.C_Str(), source, reason)) {
        scene.warnings.push_back(materialLabel(m) + ": " + reason +
                                 "; it renders with its plain colour");
        return;
    }
    if (uvIndex != 0)
        scene.warnings.push_back(materialLabel(m) + ": base-colour texture uses UV set " +
                                 std::to_string(uvIndex) + "; kiln reads UV set 0");
    readUvTransform(am, slot, assetPath, m.maps.albedoUv);
    m.albedoTexture = addTextureSource(scene, std::move(source));
    if (!statesColour) m.albedo = Color(1.0f);  // the texture alone, not the default grey
}

}  // namespace

void warnDroppedMaterialFeatures(const aiMaterial* am, const Material& m, Scene& scene) {
    auto factor = [&](const char* key, unsigned type, unsigned index, float& out) {
        return am->Get(key, type, index, out) == AI_SUCCESS;
    };
    auto warn = [&](const std::string& what) {
        scene.warnings.push_back(materialLabel(m) + ": " + what);
    };
    float roughness = 1, opacity = 1, transmission = 0, clearcoat = 0;
    // Principled materials honour roughness, specular strength, clearcoat and transmission
    // (scene/assimp_principled.cpp); a Phong or Lambert one renders as Lambert.
    bool principled = m.kind == MaterialKind::Principled;
    if (!principled && factor(AI_MATKEY_ROUGHNESS_FACTOR, roughness) && roughness < 1)
        warn("roughness " + number(roughness) + ": its glossy reflection is dropped");
    if (factor(AI_MATKEY_OPACITY, opacity) && opacity < 1 && !m.maps.hasAlpha())
        warn("opacity " + number(opacity) + " ignored: rendered opaque");
    if (!principled && factor(AI_MATKEY_TRANSMISSION_FACTOR, transmission) && transmission > 0)
        warn("transmission ignored: rendered opaque");
    if (!principled && factor(AI_MATKEY_CLEARCOAT_FACTOR, clearcoat) && clearcoat > 0)
        warn("clearcoat ignored");
    aiColor3D specular;
    bool statesSpecular = am->Get(AI_MATKEY_COLOR_SPECULAR, specular) == AI_SUCCESS;
    if (!principled && statesSpecular && (specular.r > 0 || specular.g > 0 || specular.b > 0))
        warn("specular colour dropped (Lambert)");
    // A principled material from a Phong one (readPhongSpecular) took the colour; one from
    // metallic-roughness keys (spec-gloss glTF, OBJ Pm/Pr with Ks) did not.
    if (principled && statesMetallicRoughness(am) && statesSpecular &&
        (specular.r != specular.g || specular.g != specular.b || specular.r != 1))
        warn("specular colour tint dropped (KHR_materials_specular colour; its factor is kept)");
}

void readAssimpTextures(const aiScene* as, const aiMaterial* am, const std::string& assetPath,
                        bool statesColour, Material& m, Scene& scene) {
    readBaseColour(as, am, assetPath, statesColour, m, scene);
    readAssimpMaps(as, am, assetPath, m, scene);
    for (const auto& [slot, what] : kIgnoredSlots)
        if (am->GetTextureCount(slot) > 0 && !readsTextureSlot(slot, m, assetPath)) {
            aiString ref;
            am->GetTexture(slot, 0, &ref);
            scene.warnings.push_back(materialLabel(m) + ": " + what + " '" + ref.C_Str() +
                                     "' ignored");
        }
}

}  // namespace kiln
