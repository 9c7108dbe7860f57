// --material-override and the .kiln <override> element: one material in place of every material
// of a scene (or of an included asset) that does not emit, so lights keep lighting it.
#include <charconv>
#include <filesystem>
#include <optional>
#include <utility>

#include "scene/importers.h"
#include "scene/mesh_maps.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

// "G" or "R,G,B", each in [0, 1].
bool parseAlbedo(const std::string& text, Color& albedo) {
    float v[3];
    int n = 0;
    const char* p = text.data();
    const char* end = text.data() + text.size();
    while (n < 3) {
        auto [next, ec] = std::from_chars(p, end, v[n]);
        if (ec != std::errc() || !(v[n] >= 0 && v[n] <= 1)) return false;
        ++n;
        p = next;
        if (p == end) break;
        if (*p++ != ',') return false;
    }
    if (p != end || (n != 1 && n != 3)) return false;
    albedo = n == 1 ? Color(v[0]) : Color(v[0], v[1], v[2]);
    return true;
}

SceneError noSuchMaterial(const std::string& path, const std::string& name) {
    return SceneError(path, name.empty() ? "has no <material> for --material-override"
                                         : "has no material named '" + name + "'");
}

// The material named `name` (or the first) of a .kiln file, read with every check a scene gets,
// and the file's texture sources its texture ids index.
Material materialFromFile(const std::string& path, const std::string& name,
                          std::vector<TextureSource>* textures, std::vector<std::string>* files) {
    Scene holder;
    readKilnScene(path, holder);
    if (textures) *textures = holder.textureSources;
    if (files) {
        files->push_back(path);
        files->insert(files->end(), holder.inputFiles.begin(), holder.inputFiles.end());
    }
    for (const Material& m : holder.materials)
        if (name.empty() || m.name == name) return m;
    throw noSuchMaterial(path, name);
}

// A built-in spec's material (diffuse, clay, lambertian:...); nullopt for a file spec.
std::optional<Material> builtinOverride(const std::string& spec) {
    Material m;
    m.name = "override";
    if (spec == kDiffuseOverride) {  // applied per material by overrideMaterials(scene, spec)
        m.name = kDiffuseOverride;
        return m;
    }
    if (spec == "clay") {
        m.name = "clay";
        m.albedo = Color(0.5f);
        return m;
    }
    if (spec.rfind("lambertian:", 0) == 0) {
        if (!parseAlbedo(spec.substr(11), m.albedo))
            throw SceneError(spec, "lambertian albedo must be G or R,G,B in [0, 1]");
        return m;
    }
    return std::nullopt;
}

// A file spec's .kiln file and material name (FILE, or FILE:NAME; "" for its first material).
std::pair<std::string, std::string> overrideFile(const std::string& spec) {
    auto exists = [](const std::string& p) {
        std::error_code ec;  // a name too long for the system is not there either
        return std::filesystem::exists(p, ec);
    };
    std::string path = spec, name;
    if (!exists(path)) {
        size_t colon = spec.rfind(':');
        if (colon != std::string::npos) path = spec.substr(0, colon), name = spec.substr(colon + 1);
    }
    if (!exists(path))
        throw SceneError(
            spec,
            "not a material override: use clay, diffuse, lambertian:G, lambertian:R,G,B, "
            "or a .kiln file with a <material> (FILE or FILE:NAME)");
    if (lowerExtension(path) != ".kiln")
        throw SceneError(path, "a material override file must be a .kiln scene with <material>");
    return {path, name};
}

}  // namespace

Material parseMaterialOverride(const std::string& spec, std::vector<TextureSource>* textures,
                               std::vector<std::string>* files) {
    if (std::optional<Material> m = builtinOverride(spec)) return *m;
    auto [path, name] = overrideFile(spec);
    return materialFromFile(path, name, textures, files);
}

void checkMaterialOverride(const std::string& spec) {
    if (builtinOverride(spec)) return;
    auto [path, name] = overrideFile(spec);
    checkKilnScene(path);
    if (kilnSceneLacksMaterial(path, name)) throw noSuchMaterial(path, name);
}

namespace {
bool emits(const Material& m) {
    return m.kind == MaterialKind::Emission || maxComponent(m.emission) > 0;
}
}  // namespace

void overrideMaterials(Scene& scene, const Material& m,
                       const std::vector<TextureSource>& textures) {
    // m's textures join the scene's sources (once each), its ids moved to them.
    Material placed = m;
    std::vector<int> movedTo(textures.size(), -1);
    for (int* id : textureIds(placed)) {
        if (*id < 0) continue;
        int& to = movedTo.at(size_t(*id));
        if (to < 0) {
            to = int(scene.textureSources.size());
            scene.textureSources.push_back(textures[size_t(*id)]);
        }
        *id = to;
    }
    for (Material& old : scene.materials)
        if (!emits(old)) old = placed;
}

void overrideMaterials(Scene& scene, const std::string& spec) {
    if (spec != kDiffuseOverride) {
        std::vector<TextureSource> textures;
        // A material from a file: the scene was read from it (and what it reads) too.
        Material m = parseMaterialOverride(spec, &textures, &scene.inputFiles);
        return overrideMaterials(scene, m, textures);
    }
    // Each surface keeps its base colour, textures, vertex colours and maps; only its reflection
    // becomes Lambert (a diffuse-only look, and exact Lambert shading for tests).
    for (Material& m : scene.materials)
        if (!emits(m) && m.kind != MaterialKind::Lambertian) {
            if (m.kind != MaterialKind::Principled) m.albedo = Material{}.albedo;
            m.kind = MaterialKind::Lambertian;
        }
}

}  // namespace kiln
