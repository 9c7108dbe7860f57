#include "integrators/surface_albedo.h"

#include <algorithm>
#include <cmath>

namespace kiln {
namespace {

struct Barycentric {
    float b0, b1, b2;
};

Color colourAt(const TriangleMesh& mesh, const uint32_t* idx, const Barycentric& b) {
    auto at = [&](uint32_t i) {
        const float* c = &mesh.colors[3 * size_t(i)];
        return Color(c[0], c[1], c[2]);
    };
    return at(idx[0]) * b.b0 + at(idx[1]) * b.b1 + at(idx[2]) * b.b2;
}

}  // namespace

float textureWidth(const Scene& scene, const Hit& hit, const UvTransform& uvTransform,
                   float worldWidth) {
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    const uint32_t* idx = &mesh.indices[3 * size_t(hit.prim)];
    const float* uv = mesh.uvs.data();
    float u0 = uv[2 * idx[0]], v0 = uv[2 * idx[0] + 1], u1 = uv[2 * idx[1]],
          v1 = uv[2 * idx[1] + 1], u2 = uv[2 * idx[2]], v2 = uv[2 * idx[2] + 1];
    float uvArea = std::abs((u1 - u0) * (v2 - v0) - (u2 - u0) * (v1 - v0));
    Vec3 p0 = mesh.vertex(idx[0]);
    float area = length(cross(mesh.vertex(idx[1]) - p0, mesh.vertex(idx[2]) - p0));
    if (hit.instance != kInvalidId)  // the placement's linear scale
        area *=
            std::pow(std::abs(float(scene.instances[hit.instance].objectToWorld.determinant3())),
                     2.0f / 3.0f);
    return area > 0 ? worldWidth * std::sqrt(uvArea / area) * uvTransform.areaScale() : 0.0f;
}

namespace {

// The texture lookup: (u, v) with v up, as OBJ and Assimp store it, through the texture's UV
// transform to OIIO's (s, t), t running down the image.
Color textureAt(const Scene& scene, int texture, const UvTransform& uvTransform, const Hit& hit,
                const TriangleMesh& mesh, float worldWidth) {
    float u, v;
    uvAt(mesh, hit.prim, hit.u, hit.v, u, v);
    float width = textureWidth(scene, hit, uvTransform, worldWidth);
    return scene.textures->lookup(texture, uvTransform.s(u, v), uvTransform.t(u, v), width,
                                  uvTransform.wrap);
}

float channelAt(const Scene& scene, int texture, int channel, const UvTransform& uvTransform,
                const Hit& hit, const TriangleMesh& mesh, float worldWidth) {
    float u, v;
    uvAt(mesh, hit.prim, hit.u, hit.v, u, v);
    float width = textureWidth(scene, hit, uvTransform, worldWidth);
    return scene.textures->lookupChannel(texture, channel, uvTransform.s(u, v), uvTransform.t(u, v),
                                         width, uvTransform.wrap);
}

}  // namespace

bool hasSurfaceColourVariation(const Scene& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const Material& m) {
                           return m.albedoTexture >= 0 || m.maps.normalTexture >= 0 ||
                                  m.maps.metallicTexture >= 0 || m.maps.roughnessTexture >= 0;
                       }) ||
           std::any_of(scene.meshes.begin(), scene.meshes.end(),
                       [](const TriangleMesh& m) { return !m.colors.empty(); });
}

Color albedoAt(const Scene& scene, const Material& material, const Hit& hit, float travelled,
               float pixelSpread) {
    if (hit.shape == kSphereShape) return material.albedo;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    bool textured = material.albedoTexture >= 0 && !mesh.uvs.empty() && scene.textures;
    if (!textured && mesh.colors.empty()) return material.albedo;
    const uint32_t* idx = &mesh.indices[3 * size_t(hit.prim)];
    Barycentric b{1 - hit.u - hit.v, hit.u, hit.v};
    Color albedo = material.albedo;
    if (textured)
        albedo = albedo * textureAt(scene, material.albedoTexture, material.maps.albedoUv, hit,
                                    mesh, travelled * pixelSpread);
    if (!mesh.colors.empty()) albedo = albedo * colourAt(mesh, idx, b);
    return albedo;
}

MetallicRoughness metallicRoughnessAt(const Scene& scene, const Material& material, const Hit& hit,
                                      float travelled, float pixelSpread) {
    MetallicRoughness mr = MetallicRoughness::of(material);
    const MaterialMaps& maps = material.maps;
    if (maps.metallicTexture < 0 && maps.roughnessTexture < 0) return mr;
    if (hit.shape == kSphereShape || !scene.textures) return mr;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    if (mesh.uvs.empty()) return mr;
    float worldWidth = travelled * pixelSpread;
    if (maps.metallicTexture >= 0)
        mr.metallic *= channelAt(scene, maps.metallicTexture, maps.metallicChannel, maps.metallicUv,
                                 hit, mesh, worldWidth);
    if (maps.roughnessTexture >= 0)
        mr.roughness *= channelAt(scene, maps.roughnessTexture, maps.roughnessChannel,
                                  maps.roughnessUv, hit, mesh, worldWidth);
    return mr;
}

Color emissionTexelAt(const Scene& scene, const Material& material, uint32_t mesh, uint32_t prim,
                      float b1, float b2) {
    const MaterialMaps& maps = material.maps;
    if (maps.emissionTexture < 0 || !scene.textures || mesh >= scene.meshes.size())
        return Color(1.0f);
    const TriangleMesh& m = scene.meshes[mesh];
    if (m.uvs.empty()) return Color(1.0f);
    float u, v;
    uvAt(m, prim, b1, b2, u, v);
    const UvTransform& x = maps.emissionUv;
    return scene.textures->lookup(maps.emissionTexture, x.s(u, v), x.t(u, v), 0.0f, x.wrap);
}

bool hasEmissionTexture(const Scene& scene, uint32_t mesh) {
    const TriangleMesh& m = scene.meshes[mesh];
    if (m.uvs.empty() || !scene.textures) return false;
    return std::any_of(m.materialIds.begin(), m.materialIds.end(), [&](uint32_t id) {
        return id < scene.materials.size() && scene.materials[id].maps.emissionTexture >= 0;
    });
}

}  // namespace kiln
