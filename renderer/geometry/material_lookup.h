// What a material is at a point of a surface: the one home of every per-point material lookup
// (base colour with vertex colours, metallic-roughness, emission texel, normal-map texel, alpha).
// Each texture is read the same way: the triangle's UV at the point, the map's UV transform, the
// footprint rule, then OIIO's TextureSystem (color/texture.h). It sits below the accelerators,
// which need alpha during traversal.
#pragma once

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

// A point of a triangle: barycentric weights b1, b2 of its vertices 1 and 2; `instance` places it
// (kInvalidId: the mesh is in world space), which scales the footprint.
struct MeshPoint {
    uint32_t mesh = 0, prim = 0;
    float b1 = 0, b2 = 0;
    uint32_t instance = kInvalidId;
    static MeshPoint of(const Hit& hit) {
        return {hit.shape, hit.prim, hit.u, hit.v, hit.instance};
    }
};

// Footprint rule (docs/import.md): without ray differentials, a lookup covers the width a pixel
// spans at the distance the path has travelled (travelled * pixelSpread, in scene units), mapped to
// texture space by the triangle's UV-to-surface scale, sqrt(UV area / area), and the transform's.
float textureWidth(const Scene& scene, const MeshPoint& at, const UvTransform& uvTransform,
                   float worldWidth);

// A map's colour, or one channel, at the point; worldWidth 0: the finest level.
Color mapColour(const Scene& scene, int texture, const UvTransform& uvTransform,
                const MeshPoint& at, float worldWidth);
float mapChannel(const Scene& scene, int texture, int channel, const UvTransform& uvTransform,
                 const MeshPoint& at, float worldWidth);

// Metallic and perceptual roughness at a point: the material's factors times its
// metallic-roughness texture there.
struct MetallicRoughness {
    float metallic = 0, roughness = 1;
    static MetallicRoughness of(const Material& m) { return {m.metallic, m.roughness}; }
};

// The principled clear coat's weight and perceptual roughness at a point: the material's factors
// times its clearcoat textures there (glTF clearcoatTexture R, clearcoatRoughnessTexture G).
struct Coat {
    float weight = 0, roughness = 0;
    static Coat of(const Material& m) { return {m.clearcoat, m.clearcoatRoughness}; }
};

// The principled transmission weight and sheen at a point: the material's factors times their
// textures there (glTF transmissionTexture R, sheenColorTexture RGB, sheenRoughnessTexture A).
struct Layers {
    float transmission = 0;
    Color sheenColour{0.0f};
    float sheenRoughness = 0.5f;
    static Layers of(const Material& m) { return {m.transmission, m.sheenColor, m.sheenRoughness}; }
};

// What a BSDF reads of its material at a point: the base (diffuse) colour, times its texture and
// the mesh's vertex colours, and the principled metallic, roughness, clear coat and layers.
struct SurfaceInputs {
    Color baseColour;
    MetallicRoughness mr;
    Coat coat;
    Layers layers;
    static SurfaceInputs of(const Material& m) {
        return {m.albedo, MetallicRoughness::of(m), Coat::of(m), Layers::of(m)};
    }
};

// Whether any material has a texture (colour, normal or metallic-roughness map) or any mesh vertex
// colours: else every point's inputs are the material's factors and no normal is mapped.
bool hasSurfaceColourVariation(const Scene& scene);

Color baseColourAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth);
MetallicRoughness metallicRoughnessAt(const Scene& scene, const Material& material, const Hit& hit,
                                      float worldWidth);
Coat coatAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth);
Layers layersAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth);
inline SurfaceInputs surfaceInputsAt(const Scene& scene, const Material& material, const Hit& hit,
                                     float worldWidth) {
    return {baseColourAt(scene, material, hit, worldWidth),
            metallicRoughnessAt(scene, material, hit, worldWidth),
            coatAt(scene, material, hit, worldWidth), layersAt(scene, material, hit, worldWidth)};
}

// The normal map's tangent-space normal at the hit ((2 texel - 1), xy scaled by normalScale);
// false where the material or mesh has none (no map, tangents or UVs).
bool normalMapAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth,
                 Vec3& tangentNormal);

// The emission texture's colour at the point, 1 where the material has none: it multiplies the
// emitted radiance. Read at the finest level, with no footprint, so that a ray hitting the point
// and a light sample picking it see the same radiance (MIS weighs the two as estimates of one
// integrand).
Color emissionTexelAt(const Scene& scene, const Material& material, const MeshPoint& at);
// Whether any material of the mesh has an emission texture it can read (the mesh has UVs).
bool hasEmissionTexture(const Scene& scene, uint32_t mesh);

// Alpha at the point: the material's opacity times its opacity texture, at the finest MIP level
// (no footprint is known during traversal).
float alphaAt(const Scene& scene, const Material& material, const MeshPoint& at);

}  // namespace kiln
