// KHR_materials_emissive_strength, which Assimp 5.2 does not hand over, read from the JSON.
// glTF extensions the file uses that Assimp 5.2 reads nothing of (KHR_techniques_webgl: the
// material, its texture included, silently became Assimp's default one) are named in a warning.
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
        "KHR_mesh_quantization",      "KHR_materials_emissive_strength"};
    Json doc = Json::parse(gltfJson(path), nullptr, false);
    if (!doc.is_object() || !doc.contains("extensionsUsed") || !doc["extensionsUsed"].is_array())
        return;
    for (const Json& name : doc["extensionsUsed"])
        if (name.is_string() && !read.count(name.get<std::string>()))
            scene.warnings.push_back("glTF extension " + name.get<std::string>() +
                                     " is not read: what it states (materials, textures, ...) is "
                                     "dropped");
}

std::vector<float> gltfEmissiveStrengths(const std::string& path) {
    Json doc = Json::parse(gltfJson(path), nullptr, false);
    std::vector<float> strengths;
    if (!doc.is_object() || !doc.contains("materials") || !doc["materials"].is_array())
        return strengths;
    for (const Json& m : doc["materials"]) {
        float strength = 1.0f;
        const Json* e = m.is_object() && m.contains("extensions") ? &m["extensions"] : nullptr;
        if (e && e->is_object() && e->contains("KHR_materials_emissive_strength")) {
            const Json& x = (*e)["KHR_materials_emissive_strength"];
            if (x.is_object() && x.contains("emissiveStrength") &&
                x["emissiveStrength"].is_number())
                strength = x["emissiveStrength"].get<float>();
        }
        strengths.push_back(std::isfinite(strength) ? std::max(0.0f, strength) : 1.0f);
    }
    return strengths;
}

}  // namespace kiln
