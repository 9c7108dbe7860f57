// The scene model: plain data that importers fill and accelerators/integrators read.
// Geometry is stored flat and compact so Embree can share the buffers without a copy.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "color/image_input.h"
#include "color/texture.h"
#include "renderer/core/math.h"
#include "scene/material_maps.h"

namespace kiln {

enum class MaterialKind {
    Lambertian,
    Mirror,
    Glass,
    Microfacet,
    Refraction,
    Glossy,
    Emission,
    Principled
};
const char* toString(MaterialKind kind);

struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Lambertian;
    Color albedo{0.5f};         // Lambertian diffuse colour
    Color reflectance{1.0f};    // mirror, glass, glossy
    Color transmittance{1.0f};  // glass, refraction
    float ior = 1.5f;           // glass, refraction
    float roughness = 0.0f;     // glass, refraction (CS184 files: always 0)
    float alpha = 0.1f;         // microfacet roughness (Beckmann alpha)
    Color eta{1.0f};            // microfacet conductor index of refraction per channel
    Color k{0.0f};              // microfacet conductor absorption per channel
    float shininess = 50.0f;    // glossy (Phong exponent)
    Color emission{0.0f};       // radiance emitted (Emission materials)
    int albedoTexture = -1;     // Scene::textureSources index: multiplies albedo (Lambertian)
    // Maps: normal map, alpha cutout/blend, texture transforms (scene/material_maps.h).
    MaterialMaps maps{};
    // Principled (glTF 2.0 metallic-roughness, integrators/principled_bsdf.h): base colour is
    // albedo (with albedoTexture and vertex colours), roughness is the perceptual roughness
    // (GGX alpha = roughness^2), the dielectric F0 comes from ior (1.5: 0.04) times specular,
    // emission is added to what the surface reflects.
    float metallic = 0.0f;
    float specular = 1.0f;            // KHR_materials_specular factor: scales the dielectric F0
    float clearcoat = 0.0f;           // KHR_materials_clearcoat: weight of a GGX coat, F0 0.04
    float clearcoatRoughness = 0.0f;  // its perceptual roughness
    Color specularColor{1.0f};        // KHR_materials_specular colour: tints the dielectric F0
    // KHR_materials_transmission: the share of the dielectric's diffuse part that is instead a
    // rough (GGX, same roughness) dielectric transmission tinted by the base colour, refracting
    // through ior where thickness > 0 (a closed volume) and straight through where thickness is 0
    // (thin-walled, as KHR_materials_volume).
    float transmission = 0.0f;
    float thickness = 0.0f;
    // KHR_materials_volume's absorption inside a transmissive volume (Beer-Lambert: attenuation
    // colour reached after attenuation distance): applied as the mesh's interior medium
    // (scene/volume_media.h).
    Color attenuationColor{1.0f};
    float attenuationDistance = INFINITY;
    // KHR_materials_sheen (Charlie distribution): sheen is its weight (glTF: 1), sheenColor its
    // colour, sheenRoughness its perceptual roughness.
    float sheen = 0.0f;
    Color sheenColor{1.0f};
    float sheenRoughness = 0.5f;
    // Subsurface scattering (a random walk inside the closed mesh, integrators/subsurface.h):
    // the weight blending the diffuse lobe into it, the mean free path per channel (scene units)
    // and a factor on it; the walk's albedo is the base colour.
    float subsurface = 0.0f;
    Color subsurfaceRadius{1.0f, 0.2f, 0.1f};
    float subsurfaceScale = 1.0f;
};

// A homogeneous participating medium filling the inside of the meshes that name it as their
// interior (integrators/medium.h): absorption and scattering coefficients per unit length, and
// the Henyey-Greenstein asymmetry of its phase function.
struct Medium {
    std::string name;
    Color sigmaA{0.0f}, sigmaS{0.0f};
    float g = 0.0f;
};

enum class LightKind { Area, MeshEmitter, Point, Spot, Directional, Ambient, Environment };
const char* toString(LightKind kind);

struct Light {
    std::string name;
    LightKind kind = LightKind::Point;
    Color radiance{1.0f};  // area/ambient/environment: radiance; point/spot: intensity;
                           // directional: irradiance
    Vec3 position;         // area: centre; point, spot
    Vec3 direction{0, -1,
                   0};  // area: emitting side; spot: axis; directional: direction light travels
    Vec3 dimX, dimY;    // area: full edge vectors of the rectangle
    float spotInnerDeg = 30.0f, spotOuterDeg = 45.0f;
    // Point and spot lights fall off as 1 / d^2 unless the file states another attenuation
    // 1 / (constant + linear d + quadratic d^2) (FBX through Assimp).
    bool attenuationStated = false;
    float attenuationConstant = 0, attenuationLinear = 0, attenuationQuadratic = 1;
    float falloffDenominator(float dist2) const {
        return attenuationStated ? attenuationConstant + attenuationLinear * std::sqrt(dist2) +
                                       attenuationQuadratic * dist2
                                 : dist2;
    }
    uint32_t mesh = 0;            // mesh emitter, or an area light's geometry when hasMesh
    bool hasMesh = false;         // area light whose rectangle is an emissive mesh of the scene
    std::string environmentPath;  // lat-long EXR/HDR, as named
    std::shared_ptr<const RgbImage> environmentImage;  // its pixels in the working space
    float environmentScale = 1.0f;
    float environmentRotationDeg = 0.0f;  // about the up (+Y) axis, counterclockwise from above
    bool environmentBilinear =
        false;  // between texel centres (maps the loader reads), else nearest
};

struct Camera {
    std::string name;  // as the file names it ("" for kiln's own framing)
    Vec3 position{0, 0, 5};
    Vec3 forward{0, 0, -1};
    Vec3 up{0, 1, 0};
    float hFovDeg =
        50.0f;  // full angles, as the file states them; aspect fit happens at render time
    float vFovDeg = 35.0f;
    float nearClip = 0.001f, farClip = 1e30f;
    // Which image axis a single stated fov spans (.kiln fov_axis). Fit: the file's hFov and vFov,
    // the narrower one widened to the image's aspect (today's rule; a single fov given as both is
    // then the narrow axis). Otherwise hFovDeg holds the angle and the other axis follows.
    enum class FovAxis { Fit, Horizontal, Vertical, Diagonal } fovAxis = FovAxis::Fit;
    float apertureRadius = 0.0f;  // thin lens when > 0
    float focalDistance = 1.0f;
    // Orthographic when > 0: half the view's width and height in scene units (glTF xmag/ymag,
    // COLLADA <orthographic>); the field of view and the lens are then unused, and the aspect is
    // fitted at render time as the field of view is.
    float orthoHalfWidth = 0.0f, orthoHalfHeight = 0.0f;
    bool orthographic() const { return orthoHalfWidth > 0; }
    // Only the camera's direction survives the CS184 framing rule; this is that direction
    // (from the scene centre towards the camera) when the file had a camera.
    bool fromFile = false;
    Vec3 cs184Direction{0, 0, 1};
};

// Triangles of one mesh; per-triangle material ids index Scene::materials.
struct TriangleMesh {
    std::string name;
    // The scene node that places it, when the file names one (Cryptomatte's object name, as in
    // Cycles and Arnold); empty: the mesh's own name stands for the object.
    std::string node;
    // xyz per vertex; one extra padding float at the end because Embree reads vertices as 16 bytes.
    std::vector<float> positions;
    std::vector<uint32_t> indices;      // 3 per triangle
    std::vector<float> normals;         // optional, xyz per vertex
    std::vector<float> uvs;             // optional, uv per vertex
    std::vector<float> colors;          // optional, linear rgb per vertex: multiplies the albedo
    bool colorsInWorkingSpace = false;  // decoded from sRGB codes (else linear Rec.709 as read)
    // Optional, xyz + handedness sign per vertex (4 floats): the direction of increasing u, and
    // whether the bitangent (increasing v) is +cross(n, t) or -cross(n, t). Normal maps only.
    std::vector<float> tangents;
    std::vector<uint32_t> materialIds;  // one per triangle, or one for the whole mesh
    int interior = -1;                  // Scene::media index filling the (closed) mesh, or -1

    size_t vertexCount() const { return positions.size() / 3; }
    size_t triangleCount() const { return indices.size() / 3; }
    Vec3 vertex(uint32_t i) const {
        return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
    }
    uint32_t materialOf(size_t tri) const {
        return materialIds.size() == 1 ? materialIds[0] : materialIds[tri];
    }
    void finalizePadding();  // ensures the 16-byte read past the last vertex is legal
};

struct Sphere {
    std::string name;
    Vec3 center;
    float radius = 1.0f;
    uint32_t material = 0;
};

// One placement of a mesh. A mesh named by any instance is a prototype in object space and is not
// drawn by itself; every other mesh is in world space.
struct Instance {
    uint32_t mesh = 0;
    Mat4 objectToWorld;
    Mat4 worldToObject;
    std::string node;  // the scene node of this placement, as TriangleMesh::node
    static Instance place(uint32_t mesh, const Mat4& objectToWorld, std::string node = {}) {
        return {mesh, objectToWorld, objectToWorld.inverse(), std::move(node)};
    }
};

struct Scene {
    std::string sourcePath;
    // The files the scene was read from, as opened (repeats and sourcePath itself may appear): a
    // .kiln's parts, what an importer read (.mtl, .bin, external references), a material override
    // file. Textures are in textureSources.
    std::vector<std::string> inputFiles;
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;
    std::vector<Instance> instances;
    std::vector<Material> materials;
    std::vector<Light> lights;
    std::vector<Medium> media;                  // what TriangleMesh::interior names
    std::vector<TextureSource> textureSources;  // what importers found; Material::albedoTexture
    // The sources opened for rendering (scene_loader), ids as in textureSources.
    std::shared_ptr<const TextureSet> textures;
    Camera camera;
    bool hasFileCamera = false;
    bool isCs184 =
        false;  // Z-up COLLADA, as every CS184 library file is: framed by the course rule
    bool framedByCourseRule = false;
    double loadSeconds = 0;
    std::vector<std::string> warnings;

    // Everything above is stored relative to this point (world = stored + origin): rendering near
    // the origin keeps float error bounds small for scenes placed far away (see recenterScene).
    Vec3d origin{0.0};
    uint64_t duplicateTriangles = 0;  // exact repeats of another triangle (countDuplicateTriangles)
    bool duplicatesChecked = true;    // false above the loader's size limit for that check

    std::vector<bool> prototypeMask() const;  // meshes drawn only through instances
    // Bounds in stored (recentred) coordinates; worldBoundsOf() in scene_info.h adds origin back.
    Bounds3 storedBounds() const;
    uint64_t uniqueTriangles() const;     // stored triangles
    uint64_t instancedTriangles() const;  // triangles as rendered (instances expanded)
    bool holdsNothing() const;            // no geometry, light or file camera stored yet
    // The largest radiance (intensity, irradiance) component any light, emitting material or
    // environment texel holds: sets the film's scale.
    double brightestEmission() const;

    // Stored (float) coordinates of a world point, and back; the subtraction is in double so a
    // point far from the origin keeps the precision of its distance to Scene::origin.
    Vec3 stored(const Vec3d& world) const { return Vec3(world - origin); }
    Vec3d world(const Vec3& stored) const { return Vec3d(stored) + origin; }
};

// Moves Scene::origin to `origin`, re-expressing everything stored in double (world = stored +
// origin), so nothing is rounded at the old origin's magnitude.
void rebaseScene(Scene& scene, const Vec3d& origin);

// The origin for geometry with these world bounds: their centre when they sit far from the world
// origin relative to their size (where float would round them), else the world origin, so scenes
// near it are stored exactly as parsed.
Vec3d originFor(const Bounds3T<double>& bounds);

// Readers that stream positions (PLY, OBJ) cannot know the bounds before storing: they store
// relative to the first vertex when it lies farther than this from the world origin (below it a
// float keeps 1/16384 of a unit, and files are stored exactly as parsed).
constexpr double kFarFirstVertex = 1024.0;
Vec3d streamOrigin(const Vec3d& firstVertex);

// Appends a mesh whose positions are relative to meshOrigin, re-expressed (in double) against the
// scene's origin, which it sets when the scene holds nothing yet.
void appendMesh(Scene& scene, TriangleMesh&& mesh, const Vec3d& meshOrigin);

// The origin an importer stores against: `wanted` (usually the centre of what it reads, in double)
// when the scene holds nothing yet, else the scene's own.
Vec3d adoptOrigin(Scene& scene, const Vec3d& wanted);

}  // namespace kiln
