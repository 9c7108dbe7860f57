// What a material takes from maps beyond its colour: a tangent-space normal map, alpha (cutout
// and blend coverage) and the texture transform (KHR_texture_transform) each texture is read
// through. Plain data that importers fill; the formulas that read it at a hit live here too, so
// the accelerators (alpha) and the integrators (normal map, colour) read textures alike.
#pragma once

#include <cstdint>
#include <vector>

#include "color/texture.h"
#include "renderer/core/math.h"

namespace kiln {

struct TriangleMesh;
struct Scene;
struct Material;

// Mesh UVs (v up, as OBJ and Assimp store them) to the texture lookup's (s, t) (t down the image):
// s = a*u + b*v + c, t = d*u + e*v + f. The identity transform is s = u, t = 1 - v.
struct UvTransform {
    float a = 1, b = 0, c = 0;
    float d = 0, e = -1, f = 1;
    float s(float u, float v) const { return a * u + b * v + c; }
    float t(float u, float v) const { return d * u + e * v + f; }
    // How far one unit of mesh UV goes in (s, t): the footprint rule's scale (the mean of the two
    // axes' stretch, sqrt of the determinant).
    float areaScale() const { return std::sqrt(std::abs(a * e - b * d)); }
    // How the lookup reads (s, t) outside [0, 1] (glTF sampler wrapS/wrapT), applied after the
    // transform as glTF specifies.
    WrapModes wrap;
    // glTF KHR_texture_transform (offset, rotation in radians, scale) applied in glTF's UV space
    // (v down): uv' = T * R * S * uv, R = [cos sin; -sin cos].
    static UvTransform gltf(float offsetU, float offsetV, float rotation, float scaleU,
                            float scaleV);
    // Assimp's aiUVTransform as its own TransformUVCoords step applies it (other formats).
    static UvTransform assimp(float translateU, float translateV, float rotation, float scaleU,
                              float scaleV);
};

// glTF alphaMode: Opaque ignores alpha, Mask cuts out where alpha < alphaCutoff, Blend is
// coverage (a ray passes with probability 1 - alpha, decided by a hash of the ray: the same ray
// always gets the same answer, so images stay bit-identical for any threads or tiles).
enum class AlphaMode { Opaque, Mask, Blend };
const char* toString(AlphaMode mode);

struct MaterialMaps {
    UvTransform albedoUv;      // how Material::albedoTexture is read
    int normalTexture = -1;    // Scene::textureSources index: tangent-space normals, raw data
    float normalScale = 1.0f;  // glTF normalTexture.scale: multiplies the map's x and y
    UvTransform normalUv;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float opacity = 1.0f;      // baseColorFactor alpha, OBJ d
    float alphaCutoff = 0.5f;  // Mask
    int opacityTexture = -1;   // multiplies opacity: channel opacityChannel of this texture
    int opacityChannel = 3;    // 3: the base-colour texture's alpha; 0: a grey map (OBJ map_d)
    UvTransform opacityUv;
    // Principled: the metallic and roughness factors times one channel each of these data
    // textures (glTF metallicRoughnessTexture: one texture, B metallic and G roughness; FBX/OBJ
    // metalness and roughness maps: a grey texture each, channel 0).
    int metallicTexture = -1, metallicChannel = 2;
    int roughnessTexture = -1, roughnessChannel = 1;
    UvTransform metallicUv, roughnessUv;
    // Principled: the clear coat's weight and roughness times one channel each of these data
    // textures (glTF clearcoatTexture R, clearcoatRoughnessTexture G; .kiln clearcoat-texture R).
    int clearcoatTexture = -1, clearcoatChannel = 0;
    int clearcoatRoughnessTexture = -1, clearcoatRoughnessChannel = 1;
    UvTransform clearcoatUv, clearcoatRoughnessUv;
    // Principled layers times their textures (glTF KHR_materials_transmission transmissionTexture
    // R; KHR_materials_sheen sheenColorTexture RGB, a colour map, and sheenRoughnessTexture A).
    int transmissionTexture = -1, transmissionChannel = 0;
    int sheenColorTexture = -1;
    int sheenRoughnessTexture = -1, sheenRoughnessChannel = 3;
    UvTransform transmissionUv, sheenColorUv, sheenRoughnessUv;
    // Multiplies Material::emission (glTF emissiveTexture, FBX/OBJ emissive maps): a colour map.
    int emissionTexture = -1;
    UvTransform emissionUv;
    bool hasAlpha() const { return alphaMode != AlphaMode::Opaque; }
};

}  // namespace kiln
