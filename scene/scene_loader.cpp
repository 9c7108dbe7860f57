#include "scene/scene_loader.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include "scene/framing.h"
#include "scene/importers.h"
#include "scene/mesh_maps.h"
#include "scene/scene_error.h"
#include "scene/volume_media.h"
#include "scene/working_colours.h"

namespace kiln {
namespace {

// Spheres, lights and camera from the CGL pass; sphere materials join the scene's material list.
void applyColladaExtras(const ColladaExtras& extras, Scene& scene) {
    // The extras are stored relative to their own origin, normally the scene's too.
    Vec3d shift = extras.origin - adoptOrigin(scene, extras.origin);
    auto place = [&](Vec3 p) { return Vec3(Vec3d(p) + shift); };
    std::map<std::string, uint32_t> sphereMaterial;
    for (size_t i = 0; i < extras.spheres.size(); ++i) {
        Sphere s = extras.spheres[i];
        s.center = place(s.center);
        const std::string& id = extras.sphereMaterialIds[i];
        auto known = sphereMaterial.find(id);
        if (known != sphereMaterial.end()) {
            s.material = known->second;
        } else {
            auto it = extras.materialsById.find(id);  // known (ColladaExtras' check)
            s.material = uint32_t(scene.materials.size());
            scene.materials.push_back(it == extras.materialsById.end() ? Material{"default"}
                                                                       : it->second);
            sphereMaterial[id] = s.material;
        }
        scene.spheres.push_back(s);
    }
    for (Light l : extras.lights) {
        l.position = place(l.position);
        scene.lights.push_back(l);
    }
    if (extras.camera) {
        scene.camera = *extras.camera;
        scene.camera.position = place(extras.camera->position);
        scene.hasFileCamera = true;
    }
    scene.warnings.insert(scene.warnings.end(), extras.warnings.begin(), extras.warnings.end());
}

}  // namespace

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

uint64_t countDuplicateTriangles(const Scene& scene) {
    // Hash each triangle's sorted vertex positions, sort the hashes, then confirm equal neighbours
    // exactly: about 10x faster than a hash set of positions and 16 bytes per triangle.
    struct Entry {
        uint64_t hash;
        uint32_t mesh, tri;
    };
    auto sorted = [&](uint32_t m, uint32_t t) {
        const TriangleMesh& mesh = scene.meshes[m];
        std::array<Vec3, 3> p = {mesh.vertex(mesh.indices[3 * t]),
                                 mesh.vertex(mesh.indices[3 * t + 1]),
                                 mesh.vertex(mesh.indices[3 * t + 2])};
        std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
            return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
        });
        return p;
    };
    std::vector<bool> proto = scene.prototypeMask();
    std::vector<Entry> entries;
    entries.reserve(scene.uniqueTriangles());
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        if (!proto[m])
            for (uint32_t t = 0; t < scene.meshes[m].triangleCount(); ++t)
                entries.push_back({0, m, t});
    tbb::parallel_for(tbb::blocked_range<size_t>(0, entries.size(), 1 << 16),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i) {
                              auto p = sorted(entries[i].mesh, entries[i].tri);
                              uint64_t h = 1469598103934665603ull;
                              for (const Vec3& v : p)
                                  for (float f : {v.x, v.y, v.z})
                                      h = (h ^ std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f)) *
                                          1099511628211ull;
                              entries[i].hash = h;
                          }
                      });
    tbb::parallel_sort(entries.begin(), entries.end(),
                       [](const Entry& a, const Entry& b) { return a.hash < b.hash; });
    uint64_t duplicates = 0;
    for (size_t i = 1; i < entries.size(); ++i) {
        if (entries[i].hash != entries[i - 1].hash) continue;
        // Same hash: a duplicate of any earlier entry in the run with exactly the same positions.
        auto p = sorted(entries[i].mesh, entries[i].tri);
        for (size_t j = i; j-- > 0 && entries[j].hash == entries[i].hash;)
            if (sorted(entries[j].mesh, entries[j].tri) == p) {
                ++duplicates;
                break;
            }
    }
    return duplicates;
}

void recenterScene(Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return;
    Vec3 c = b.centroid();
    // Only worth it when the scene sits far from its origin relative to its size (near the origin
    // a shift would only round every coordinate once more).
    if (maxComponent(abs(c)) <= 4 * maxComponent(b.diagonal())) return;
    rebaseScene(scene, scene.origin + Vec3d(c));
}

void checkSceneFileOpens(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw SceneError(path, "no such file");
    if (std::filesystem::is_directory(path, ec))
        throw SceneError(path, "is a directory, not a scene file");
    // Before any open: opening a FIFO blocks until a writer comes, signals and all.
    if (!std::filesystem::is_regular_file(path, ec))
        throw SceneError(path,
                         "is not a regular file (a FIFO, socket or device), not a scene file");
    if (!std::ifstream(path).good()) throw SceneError(path, "cannot read file (permission?)");
    if (std::filesystem::file_size(path, ec) == 0) throw SceneError(path, "file is empty");
}

void importFile(const std::string& path, Scene& scene) {
    checkSceneFileOpens(path);

    std::string ext = lowerExtension(path);
    if (ext == ".ply") {
        readPly(path, scene);
    } else if (ext == ".obj") {
        if (!readObj(path, scene)) {
            checkObjIndices(path);
            importWithAssimp(path, nullptr, scene);
        }
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

namespace {

// Importers check sizes before allocating; a library (Assimp) that does not still must not end in
// a raw bad_alloc.
void importOrRefuse(const std::string& path, Scene& scene) {
    try {
        importFile(path, scene);
    } catch (const std::bad_alloc&) {
        throw SceneError(path,
                         "out of memory while reading the file (sizes it declares are "
                         "larger than this machine can hold)");
    } catch (const std::length_error& e) {
        throw SceneError(path,
                         std::string("sizes the file declares are impossible (") + e.what() + ")");
    }
}

// Lights that add nothing (zero radiance, zero-area rectangles, closed spot cones), each named.
void warnDarkLights(Scene& scene) {
    size_t dark = 0;
    for (const Light& l : scene.lights) {
        bool zero =
            !(maxComponent(l.radiance) > 0) ||
            (l.kind == LightKind::Area && !l.hasMesh && !(length(cross(l.dimX, l.dimY)) > 0)) ||
            (l.kind == LightKind::Spot && !(l.spotOuterDeg > 0));
        if (!zero) continue;
        ++dark;
        scene.warnings.push_back("light '" + l.name + "' (" + toString(l.kind) +
                                 ") has zero power and lights nothing");
    }
    if (dark > 0 && dark == scene.lights.size())
        scene.warnings.push_back("every light has zero power: only emission will be visible");
}

// Reasons an image will be black that the scene shows before any ray (each says which).
void warnBlackImage(Scene& scene) {
    std::vector<uint32_t> used;
    for (const TriangleMesh& m : scene.meshes)
        used.insert(used.end(), m.materialIds.begin(), m.materialIds.end());
    for (const Sphere& s : scene.spheres) used.push_back(s.material);
    bool anyVisible = false;
    for (uint32_t id : used) {
        const Material& m = scene.materials[id];
        anyVisible |= m.kind != MaterialKind::Lambertian || maxComponent(m.albedo) > 0 ||
                      m.albedoTexture >= 0 || maxComponent(m.emission) > 0;
    }
    if (!anyVisible && !used.empty())
        scene.warnings.push_back(
            "every material's diffuse colour is black, as the file states, "
            "and nothing emits: the image will be black");
    // Whether the lights are too dim or far is decided from what the camera sees, when kiln render
    // probes the frame (renderer/frame_probe.h): no threshold on light power alone can tell.
}

// A camera whose clip range (near and far planes, along its view axis) lies wholly in front of or
// behind every object sees none of them: the image is black (a COLLADA camera node scaled by 1e3
// scales znear and zfar too, putting the near plane beyond the scene). Named with the numbers.
void warnClipRange(Scene& scene) {
    const Camera& c = scene.camera;
    Bounds3 b = scene.storedBounds();
    if (b.empty() || !(length(c.forward) > 0)) return;
    Vec3 axis = normalize(c.forward);
    float nearest = std::numeric_limits<float>::infinity(), farthest = -nearest;
    for (int k = 0; k < 8; ++k) {
        Vec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                    (k & 4) ? b.hi.z : b.lo.z);
        float z = dot(corner - c.position, axis);
        nearest = std::min(nearest, z), farthest = std::max(farthest, z);
    }
    if (!(c.nearClip > farthest || c.farClip < nearest)) return;
    scene.warnings.push_back(fmt::format(
        "camera '{}': its clip range {:.4g} .. {:.4g} (along the view axis) excludes every "
        "object, which lie {:.4g} .. {:.4g} in front of it: the image will show no geometry",
        c.name.empty() ? "(default)" : c.name, double(c.nearClip), double(c.farClip),
        double(nearest), double(farthest)));
}

// Beyond 2^24 / 100 the float spacing at the scene's far edge exceeds 1% of a typical edge.
void warnFloatResolution(Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return;
    double reach = std::max(maxComponent(abs(b.lo)), maxComponent(abs(b.hi)));
    double edges = 0;
    uint64_t counted = 0;
    for (const TriangleMesh& m : scene.meshes)
        for (size_t t = 0; t < m.triangleCount() && counted < 100000; ++t, ++counted)
            edges += length(m.vertex(m.indices[3 * t + 1]) - m.vertex(m.indices[3 * t]));
    if (counted == 0 || !(edges > 0)) return;
    double typical = edges / double(counted), spacing = reach * std::ldexp(1.0, -24);
    if (spacing > 0.01 * typical) {
        scene.warnings.push_back(
            fmt::format("the scene reaches {:.3g} units from its centre but its edges are about "
                        "{:.3g} long: float spacing there ({:.3g}) blurs details",
                        reach, typical, spacing));
    }
}

// The --env map's light, read before the scene (it needs nothing of it): a missing or malformed
// map is refused before a 100M-triangle import, not a minute after.
std::optional<Light> environmentLight(const LoadOptions& options,
                                      std::vector<std::string>& warnings) {
    if (options.environmentMap.empty()) return std::nullopt;
    // The error_code form: a name too long for the file system is "no such map", not a throw.
    if (std::error_code ec; !std::filesystem::exists(options.environmentMap, ec))
        throw SceneError(options.environmentMap, "no such environment map");
    Light env;
    env.environmentImage = loadEnvironmentMap(options.environmentMap, warnings);
    env.name = "environment";
    env.kind = LightKind::Environment;
    env.environmentPath = options.environmentMap;
    env.environmentScale = options.environmentScale;
    env.environmentRotationDeg = options.environmentRotationDeg;
    env.radiance = Color(options.environmentScale);
    env.environmentBilinear = true;
    return env;
}

std::atomic<uint64_t>& loadCounter() {
    static std::atomic<uint64_t> count{0};
    return count;
}

}  // namespace

uint64_t sceneLoadCount() { return loadCounter().load(); }

Scene loadScene(const std::string& path, const LoadOptions& options) {
    ++loadCounter();
    auto start = std::chrono::steady_clock::now();
    Scene scene;
    scene.sourcePath = path;
    // Checked before the (maybe long) import: a bad spec or map is a quick one-line error.
    if (!options.materialOverride.empty()) parseMaterialOverride(options.materialOverride);
    const std::optional<Light> environment = environmentLight(options, scene.warnings);
    importOrRefuse(path, scene);
    std::string ext = lowerExtension(path);
    if (!options.materialOverride.empty()) overrideMaterials(scene, options.materialOverride);
    validateScene(scene);
    addVolumeMedia(scene);
    addMissingTangents(scene);
    recenterScene(scene);
    warnFloatResolution(scene);
    // The check costs about 0.1 s per million triangles (random vertex reads and a sort): above 20M
    // the tie rule for exact duplicates is not enforced (kiln info says so).
    constexpr uint64_t kDuplicateCheckLimit = 20'000'000;
    scene.duplicatesChecked = scene.uniqueTriangles() <= kDuplicateCheckLimit;
    scene.duplicateTriangles = scene.duplicatesChecked ? countDuplicateTriangles(scene) : 0;
    if (scene.duplicateTriangles)
        scene.warnings.push_back(std::to_string(scene.duplicateTriangles) +
                                 " triangles repeat another exactly; where they overlap the "
                                 "lowest-numbered one is shown");

    addEmissiveMeshLights(scene);
    mergeAreaLightsWithEmitters(scene);
    bool hasLight = !scene.lights.empty();
    if (!options.emissiveMeshLights)
        std::erase_if(scene.lights,
                      [](const Light& l) { return l.kind == LightKind::MeshEmitter; });
    if (environment) scene.lights.push_back(*environment);
    openTextures(scene, options.textureCacheMb);
    if (!hasLight && options.environmentMap.empty()) {
        // Bare meshes expect the default rig; a scene file that forgot its lights gets a warning.
        if (ext == ".dae" || ext == ".gltf" || ext == ".glb" || ext == ".fbx")
            scene.warnings.push_back("scene has no lights; using the default light rig");
        addDefaultLightRig(scene);
    }
    convertColoursToWorkingSpace(scene);
    warnDarkLights(scene);
    warnBlackImage(scene);

    using Rule = LoadOptions::CameraRule;
    // The course rule places a perspective camera by its field of view: an orthographic camera
    // keeps the view the file gives it.
    bool courseRule =
        options.cameraRule == Rule::Framed || (options.cameraRule == Rule::Auto && scene.isCs184);
    if (courseRule && scene.hasFileCamera && scene.camera.orthographic()) {
        if (options.cameraRule == Rule::Framed)
            scene.warnings.push_back(
                "the camera is orthographic: the CS184 framing rule does not apply to it");
        courseRule = false;
    }
    if (!scene.hasFileCamera)
        applyDefaultFraming(scene);
    else if (courseRule)
        applyCs184Framing(scene);
    scene.framedByCourseRule = scene.hasFileCamera && courseRule;

    validateView(scene);
    warnClipRange(scene);
    scene.loadSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return scene;
}

}  // namespace kiln
