// Loads any supported scene file into the scene model, validates it and completes it (camera
// framing, default lights for bare meshes, environment light on request).
#pragma once

#include <string>

#include "renderer/core/enum_names.h"
#include "scene/scene.h"

namespace kiln {

struct LoadOptions {
    // Camera rule: Auto frames CS184-library COLLADA (Z-up, as every course file is) by the course
    // rule and uses the file camera elsewhere; File and Framed force one or the other.
    enum class CameraRule { Auto, File, Framed } cameraRule = CameraRule::Auto;
    std::string environmentMap;  // --env: adds a lat-long environment light
    // false (--emitters camera, the CS184 program): emissive meshes that are not an area light's
    // quad are no lights; the path tracer then shows them to camera rays only (PathOptions).
    bool emissiveMeshLights = true;
    float environmentScale = 1.0f;                       // --env-strength
    float environmentRotationDeg = 0.0f;                 // --env-rotate, about the up axis
    float textureCacheMb = TextureSet::kDefaultCacheMb;  // --texture-cache-mb
    // --material-override: replaces every material that does not emit (spec or file, see
    // parseMaterialOverride); empty: the file's materials.
    std::string materialOverride;

    bool operator==(const LoadOptions&) const = default;  // the same load (kiln render-frames)
};

// --camera's names (Auto is the default, not a name to give).
template <>
struct EnumNames<LoadOptions::CameraRule> {
    static constexpr std::pair<LoadOptions::CameraRule, const char*> table[] = {
        {LoadOptions::CameraRule::File, "file"}, {LoadOptions::CameraRule::Framed, "framed"}};
};

// The material a --material-override names: "clay" (Lambert grey 0.5), "diffuse" (see below),
// "lambertian:G" or
// "lambertian:R,G,B", or a .kiln file with a <material> (FILE, or FILE:NAME for one of several).
// Throws SceneError naming the spec or file. `textures` (if given) receives a file's texture
// sources, which the material's texture ids index; `files` (if given) gains the file and the files
// it read when the material came from one.
Material parseMaterialOverride(const std::string& spec,
                               std::vector<TextureSource>* textures = nullptr,
                               std::vector<std::string>* files = nullptr);
// The spec's form and, for a file, the file's whole .kiln tree, importing none of its meshes (a
// <override spec> is checked before a scene's first part is imported), and its material's name
// where the file itself settles it (a name only a part's import could bring is looked up when the
// override is applied).
void checkMaterialOverride(const std::string& spec);

// Replaces every material of the scene that does not emit by `m` (emitters keep lighting it); m's
// texture ids index `textures`, which join the scene's sources.
void overrideMaterials(Scene& scene, const Material& m, const std::vector<TextureSource>& textures);
// The same for a spec; "diffuse" keeps every material's base colour, textures and maps and makes
// it reflect as Lambert.
void overrideMaterials(Scene& scene, const std::string& spec);
constexpr const char* kDiffuseOverride = "diffuse";

// Throws SceneError (one line: file and problem) on anything it cannot load.
Scene loadScene(const std::string& path, const LoadOptions& options = {});
// How many times this process has called loadScene (what kiln render-frames reports, so a batch
// shows it loaded each scene once).
uint64_t sceneLoadCount();

// Checks the geometry: finite vertices, indices in range, something to render (triangles of zero
// area do not count; a mesh made only of them is a warning).
void validateScene(Scene& scene);

// Checks, before any ray is traced, what would make rays invalid: a camera with no direction, a
// field of view outside (0, 180), clip planes out of order, a scene extent float cannot trace.
void validateView(const Scene& scene);
// The same with the scene's storedBounds() found already (a camera option's frame of a batch).
void validateView(const Scene& scene, const Bounds3& storedBounds);
void validateCamera(const std::string& file, const Camera& camera);

// Largest extent (after recentring) kiln traces: beyond it squared distances leave float's range.
constexpr float kMaxSceneExtent = 1e15f;

// Lights for files that bring none: a key directional light and a dim sky (ambient) fill.
void addDefaultLightRig(Scene& scene);

// Opens a lat-long environment map to check it (SceneError if unreadable); warns if it is not 2:1.
// Reads and checks an environment map (a clear SceneError before any rendering).
std::shared_ptr<const RgbImage> loadEnvironmentMap(const std::string& path,
                                                   std::vector<std::string>& warnings);

// Opens Scene::textureSources into Scene::textures (a cache of cacheMb); a texture that cannot be
// read is a warning and its materials keep their plain colour.
void openTextures(Scene& scene, float cacheMb);

// Adds a light for every mesh whose material emits (sampled by area at render time).
void addEmissiveMeshLights(Scene& scene);

// Moves the scene so its bounds are centred on the origin (recording the shift in Scene::origin).
// Float error bounds grow with coordinate magnitude: a 2-unit box placed at 1e6 would otherwise
// render with ray offsets of about 0.1 unit. Subtracting a centre of the same magnitude is exact
// (Sterbenz).
void recenterScene(Scene& scene);

// Triangles whose three vertex positions repeat an earlier triangle of a world-space mesh.
uint64_t countDuplicateTriangles(const Scene& scene);

// Binds each area light to the emissive mesh that occupies its rectangle (CS184 boxes have both).
void mergeAreaLightsWithEmitters(Scene& scene);

}  // namespace kiln
