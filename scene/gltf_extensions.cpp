// KHR_materials_emissive_strength and KHR_materials_specular, which Assimp 5.2 does not hand over,
// read from the JSON. glTF extensions the file uses that Assimp 5.2 reads nothing of
// (KHR_techniques_webgl: the material, its texture included, silently became Assimp's default
// one) are named in one warning.
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include "renderer/core/json.h"
#include "scene/importers.h"

namespace kiln {
namespace {

// The JSON text of a .gltf, or of a .glb's first chunk; empty when unreadable (Assimp reports).
std::string gltfJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char header[20] = {};
    if (!in.read(header, sizeof header)) return {};
    if (std::memcmp(header, "glTF", 4) != 0) {
        in.seekg(0);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    uint32_t length = 0;
    std::memcpy(&length, header + 12, 4);  // chunk 0: length, type "JSON", then the text
    if (std::memcmp(header + 16, "JSON", 4) != 0 || length > (1u << 30)) return {};
    std::string text(length, '\0');
    return in.read(text.data(), length) ? text : std::string();
}

}  // namespace

void warnUnreadGltfExtensions(const std::string& path, Scene& scene) {
    // What kiln renders, approximates with its own warning, or Assimp decodes into plain data.
    static const std::set<std::string> read = {
        "KHR_lights_punctual",        "KHR_draco_mesh_compression",
        "KHR_texture_transform",      "KHR_materials_clearcoat",
        "KHR_materials_transmission", "KHR_materials_pbrSpecularGlossiness",
        "KHR_mesh_quantization",      "KHR_materials_emissive_strength",
        "KHR_materials_sheen",        "KHR_materials_volume",
        "KHR_materials_ior",          "KHR_materials_specular"};
    Json doc = Json::parse(gltfJson(path), nullptr, false);
    if (!doc.is_object() || !doc.contains("extensionsUsed") || !doc["extensionsUsed"].is_array())
        return;
    std::string unread;
    for (const Json& name : doc["extensionsUsed"])
        if (name.is_string() && !read.count(name.get<std::string>()))
            unread += (unread.empty() ? "" : ", ") + name.get<std::string>();
    if (!unread.empty())
        scene.warnings.push_back(
            "glTF extensions not read (what they state: materials, "
            "textures, ... is dropped): " +
            unread);
}

namespace {

float number(const Json& object, const char* key, float fallback) {
    if (!object.contains(key) || !object[key].is_number()) return fallback;
    float v = object[key].get<float>();
    return std::isfinite(v) ? v : fallback;
}

// KHR_materials_specular, which Assimp 5.2 does not hand over.
void readSpecular(const Json& x, GltfMaterialExtras& out) {
    out.specular = std::max(0.0f, number(x, "specularFactor", 1.0f));
    if (x.contains("specularColorFactor") && x["specularColorFactor"].is_array() &&
        x["specularColorFactor"].size() == 3) {
        const Json& c = x["specularColorFactor"];
        if (c[0].is_number() && c[1].is_number() && c[2].is_number())
            out.specularColour =
                max(Color(c[0].get<float>(), c[1].get<float>(), c[2].get<float>()), Color(0.0f));
    }
    for (const char* texture : {"specularTexture", "specularColorTexture"})
        if (x.contains(texture)) out.unreadTextures.push_back(texture);
}

}  // namespace

std::vector<GltfMaterialExtras> gltfMaterialExtras(const std::string& path) {
    Json doc = Json::parse(gltfJson(path), nullptr, false);
    std::vector<GltfMaterialExtras> extras;
    if (!doc.is_object() || !doc.contains("materials") || !doc["materials"].is_array())
        return extras;
    for (const Json& m : doc["materials"]) {
        GltfMaterialExtras& out = extras.emplace_back();
        const Json* e = m.is_object() && m.contains("extensions") ? &m["extensions"] : nullptr;
        if (!e || !e->is_object()) continue;
        if (e->contains("KHR_materials_emissive_strength") &&
            (*e)["KHR_materials_emissive_strength"].is_object())
            out.emissiveStrength = std::max(
                0.0f, number((*e)["KHR_materials_emissive_strength"], "emissiveStrength", 1.0f));
        if (e->contains("KHR_materials_specular") && (*e)["KHR_materials_specular"].is_object())
            readSpecular((*e)["KHR_materials_specular"], out);
    }
    return extras;
}

}  // namespace kiln
