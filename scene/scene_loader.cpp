#include "scene/scene_loader.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <unordered_set>

#include "scene/framing.h"
#include "scene/importers.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// Spheres, lights and camera from the CGL pass; sphere materials join the scene's material list.
void applyColladaExtras(const ColladaExtras& extras, Scene& scene) {
    std::map<std::string, uint32_t> sphereMaterial;
    for (size_t i = 0; i < extras.spheres.size(); ++i) {
        Sphere s = extras.spheres[i];
        const std::string& id = extras.sphereMaterialIds[i];
        auto known = sphereMaterial.find(id);
        if (known != sphereMaterial.end()) {
            s.material = known->second;
        } else {
            auto it = extras.materialsById.find(id);
            if (!id.empty() && it == extras.materialsById.end())
                throw SceneError(scene.sourcePath,
                                 "sphere '" + s.name + "' binds unknown material '" + id + "'");
            s.material = uint32_t(scene.materials.size());
            scene.materials.push_back(it == extras.materialsById.end() ? Material{"default"}
                                                                       : it->second);
            sphereMaterial[id] = s.material;
        }
        scene.spheres.push_back(s);
    }
    scene.lights.insert(scene.lights.end(), extras.lights.begin(), extras.lights.end());
    if (extras.camera) {
        scene.camera = *extras.camera;
        scene.hasFileCamera = true;
    }
    scene.warnings.insert(scene.warnings.end(), extras.warnings.begin(), extras.warnings.end());
}

}  // namespace

uint64_t countDuplicateTriangles(const Scene& scene) {
    struct Key {
        std::array<float, 9> v;
        bool operator==(const Key& o) const { return v == o.v; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            size_t h = 0;
            for (float f : k.v) h = h * 1000003u ^ std::hash<float>()(f);
            return h;
        }
    };
    std::unordered_set<Key, KeyHash> seen;
    std::vector<bool> proto = scene.prototypeMask();
    uint64_t duplicates = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (proto[m]) continue;
        const TriangleMesh& mesh = scene.meshes[m];
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            std::array<Vec3, 3> p = {mesh.vertex(mesh.indices[3 * t]),
                                     mesh.vertex(mesh.indices[3 * t + 1]),
                                     mesh.vertex(mesh.indices[3 * t + 2])};
            std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
                return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
            });
            Key k{{p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z}};
            duplicates += !seen.insert(k).second;
        }
    }
    return duplicates;
}

void recenterScene(Scene& scene) {
    Bounds3 b = scene.worldBounds();
    if (b.empty()) return;
    Vec3 c = b.centroid();
    // Only worth it (and only exact) when the scene sits far from the origin relative to its size.
    if (maxComponent(abs(c)) <= 4 * maxComponent(b.diagonal())) return;
    std::vector<bool> proto = scene.prototypeMask();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (proto[m]) continue;  // prototypes live in object space
        std::vector<float>& p = scene.meshes[m].positions;
        for (size_t v = 0; v + 2 < p.size(); v += 3) p[v] -= c.x, p[v + 1] -= c.y, p[v + 2] -= c.z;
    }
    for (Instance& inst : scene.instances) {
        for (int r = 0; r < 3; ++r) inst.objectToWorld.m[r][3] -= double(c[r]);
        inst.worldToObject = inst.objectToWorld.inverse();
    }
    for (Sphere& s : scene.spheres) s.center -= c;
    for (Light& l : scene.lights) l.position -= c;
    scene.camera.position -= c;
    scene.origin = Vec3d(c);
}

void importFile(const std::string& path, Scene& scene) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw SceneError(path, "no such file");
    if (std::filesystem::is_directory(path, ec))
        throw SceneError(path, "is a directory, not a scene file");
    if (!std::ifstream(path).good()) throw SceneError(path, "cannot read file (permission?)");
    if (std::filesystem::file_size(path, ec) == 0) throw SceneError(path, "file is empty");

    std::string ext = lowerExtension(path);
    if (ext == ".ply") {
        readPly(path, scene);
    } else if (ext == ".kiln") {
        readKilnScene(path, scene);
    } else if (ext == ".dae") {
        ColladaExtras extras = parseColladaExtras(path);
        importWithAssimp(path, &extras, scene);
        applyColladaExtras(extras, scene);
        scene.isCs184 = extras.zUp;
    } else {
        importWithAssimp(path, nullptr, scene);
    }
}

Scene loadScene(const std::string& path, const LoadOptions& options) {
    auto start = std::chrono::steady_clock::now();
    Scene scene;
    scene.sourcePath = path;
    importFile(path, scene);
    std::string ext = lowerExtension(path);
    validateScene(scene);
    recenterScene(scene);
    scene.duplicateTriangles = countDuplicateTriangles(scene);
    if (scene.duplicateTriangles)
        scene.warnings.push_back(std::to_string(scene.duplicateTriangles) +
                                 " triangles repeat another exactly; where they overlap the "
                                 "lowest-numbered one is shown");

    addEmissiveMeshLights(scene);
    mergeAreaLightsWithEmitters(scene);
    bool hasLight = !scene.lights.empty();
    if (!options.environmentMap.empty()) {
        if (!std::filesystem::exists(options.environmentMap))
            throw SceneError(options.environmentMap, "no such environment map");
        checkEnvironmentMap(options.environmentMap, scene.warnings);
        Light env;
        env.name = "environment";
        env.kind = LightKind::Environment;
        env.environmentPath = options.environmentMap;
        env.environmentScale = options.environmentScale;
        env.radiance = Color(options.environmentScale);
        scene.lights.push_back(env);
    }
    if (!hasLight && options.environmentMap.empty()) {
        // Bare meshes expect the default rig; a scene file that forgot its lights gets a warning.
        if (ext == ".dae" || ext == ".gltf" || ext == ".glb" || ext == ".fbx")
            scene.warnings.push_back("scene has no lights; using the default light rig");
        addDefaultLightRig(scene);
    }
    bool allDark = std::all_of(scene.lights.begin(), scene.lights.end(),
                               [](const Light& l) { return maxComponent(l.radiance) <= 0; });
    if (allDark)
        scene.warnings.push_back("every light has zero power: only emission will be visible");

    using Rule = LoadOptions::CameraRule;
    if (!scene.hasFileCamera)
        applyDefaultFraming(scene);
    else if (options.cameraRule == Rule::Framed ||
             (options.cameraRule == Rule::Auto && scene.isCs184))
        applyCs184Framing(scene);
    scene.framedByCourseRule =
        scene.hasFileCamera &&
        (options.cameraRule == Rule::Framed || (options.cameraRule == Rule::Auto && scene.isCs184));

    scene.loadSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return scene;
}

}  // namespace kiln
