#include "renderer/geometry/material_lookup.h"

#include <algorithm>
#include <cmath>

#include "scene/mesh_maps.h"

namespace kiln {
namespace {

struct TexCoord {
    float s, t;
};

// The point's mesh UV (v up, as OBJ and Assimp store it) through the map's transform to OIIO's
// (s, t), t running down the image.
TexCoord texCoordAt(const TriangleMesh& mesh, const MeshPoint& at, const UvTransform& x) {
    float u, v;
    uvAt(mesh, at.prim, at.b1, at.b2, u, v);
    return {x.s(u, v), x.t(u, v)};
}

float widthAt(const Scene& scene, const MeshPoint& at, const UvTransform& x, float worldWidth) {
    return worldWidth > 0 ? textureWidth(scene, at, x, worldWidth) : 0.0f;
}

Color vertexColourAt(const TriangleMesh& mesh, const Hit& hit) {
    const uint32_t* idx = &mesh.indices[3 * size_t(hit.prim)];
    auto at = [&](uint32_t i) {
        const float* c = &mesh.colors[3 * size_t(i)];
        return Color(c[0], c[1], c[2]);
    };
    return at(idx[0]) * (1 - hit.u - hit.v) + at(idx[1]) * hit.u + at(idx[2]) * hit.v;
}

// The mesh a texture lookup reads at the hit, or nullptr (a sphere, no textures, no UVs).
const TriangleMesh* texturedMesh(const Scene& scene, const Hit& hit) {
    if (hit.shape == kSphereShape || !scene.textures) return nullptr;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    return mesh.uvs.empty() ? nullptr : &mesh;
}

}  // namespace

float textureWidth(const Scene& scene, const MeshPoint& at, const UvTransform& uvTransform,
                   float worldWidth) {
    const TriangleMesh& mesh = scene.meshes[at.mesh];
    const uint32_t* idx = &mesh.indices[3 * size_t(at.prim)];
    const float* uv = mesh.uvs.data();
    float u0 = uv[2 * idx[0]], v0 = uv[2 * idx[0] + 1], u1 = uv[2 * idx[1]],
          v1 = uv[2 * idx[1] + 1], u2 = uv[2 * idx[2]], v2 = uv[2 * idx[2] + 1];
    float uvArea = std::abs((u1 - u0) * (v2 - v0) - (u2 - u0) * (v1 - v0));
    Vec3 p0 = mesh.vertex(idx[0]);
    float area = length(cross(mesh.vertex(idx[1]) - p0, mesh.vertex(idx[2]) - p0));
    if (at.instance != kInvalidId)  // the placement's linear scale
        area *= std::pow(std::abs(float(scene.instances[at.instance].objectToWorld.determinant3())),
                         2.0f / 3.0f);
    return area > 0 ? worldWidth * std::sqrt(uvArea / area) * uvTransform.areaScale() : 0.0f;
}

Color mapColour(const Scene& scene, int texture, const UvTransform& uvTransform,
                const MeshPoint& at, float worldWidth) {
    TexCoord st = texCoordAt(scene.meshes[at.mesh], at, uvTransform);
    return scene.textures->lookup(texture, st.s, st.t, widthAt(scene, at, uvTransform, worldWidth),
                                  uvTransform.wrap);
}

float mapChannel(const Scene& scene, int texture, int channel, const UvTransform& uvTransform,
                 const MeshPoint& at, float worldWidth) {
    TexCoord st = texCoordAt(scene.meshes[at.mesh], at, uvTransform);
    return scene.textures->lookupChannel(texture, channel, st.s, st.t,
                                         widthAt(scene, at, uvTransform, worldWidth),
                                         uvTransform.wrap);
}

bool hasSurfaceColourVariation(const Scene& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const Material& m) {
                           return m.albedoTexture >= 0 || m.maps.normalTexture >= 0 ||
                                  m.maps.metallicTexture >= 0 || m.maps.roughnessTexture >= 0 ||
                                  m.maps.clearcoatTexture >= 0 ||
                                  m.maps.clearcoatRoughnessTexture >= 0 ||
                                  m.maps.transmissionTexture >= 0 ||
                                  m.maps.sheenColorTexture >= 0 ||
                                  m.maps.sheenRoughnessTexture >= 0;
                       }) ||
           std::any_of(scene.meshes.begin(), scene.meshes.end(),
                       [](const TriangleMesh& m) { return !m.colors.empty(); });
}

Color baseColourAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth) {
    if (hit.shape == kSphereShape) return material.albedo;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    bool textured = material.albedoTexture >= 0 && texturedMesh(scene, hit);
    Color albedo = material.albedo;
    if (textured)
        albedo = albedo * mapColour(scene, material.albedoTexture, material.maps.albedoUv,
                                    MeshPoint::of(hit), worldWidth);
    if (!mesh.colors.empty()) albedo = albedo * vertexColourAt(mesh, hit);
    return albedo;
}

namespace {

// A factor's data texture: which channel multiplies it, read through which transform.
struct ChannelMap {
    int texture, channel;
    const UvTransform& uv;
};

// Two factors, each times its map's channel at the hit where it has a map and the mesh UVs.
void scaleByMaps(const Scene& scene, const Hit& hit, float worldWidth, float& a, ChannelMap mapA,
                 float& b, ChannelMap mapB) {
    if (mapA.texture < 0 && mapB.texture < 0) return;
    if (!texturedMesh(scene, hit)) return;
    MeshPoint at = MeshPoint::of(hit);
    if (mapA.texture >= 0)
        a *= mapChannel(scene, mapA.texture, mapA.channel, mapA.uv, at, worldWidth);
    if (mapB.texture >= 0)
        b *= mapChannel(scene, mapB.texture, mapB.channel, mapB.uv, at, worldWidth);
}

}  // namespace

MetallicRoughness metallicRoughnessAt(const Scene& scene, const Material& material, const Hit& hit,
                                      float worldWidth) {
    MetallicRoughness mr = MetallicRoughness::of(material);
    const MaterialMaps& maps = material.maps;
    scaleByMaps(scene, hit, worldWidth, mr.metallic,
                {maps.metallicTexture, maps.metallicChannel, maps.metallicUv}, mr.roughness,
                {maps.roughnessTexture, maps.roughnessChannel, maps.roughnessUv});
    return mr;
}

Coat coatAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth) {
    Coat coat = Coat::of(material);
    const MaterialMaps& maps = material.maps;
    scaleByMaps(scene, hit, worldWidth, coat.weight,
                {maps.clearcoatTexture, maps.clearcoatChannel, maps.clearcoatUv}, coat.roughness,
                {maps.clearcoatRoughnessTexture, maps.clearcoatRoughnessChannel,
                 maps.clearcoatRoughnessUv});
    return coat;
}

Layers layersAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth) {
    Layers layers = Layers::of(material);
    const MaterialMaps& maps = material.maps;
    scaleByMaps(scene, hit, worldWidth, layers.transmission,
                {maps.transmissionTexture, maps.transmissionChannel, maps.transmissionUv},
                layers.sheenRoughness,
                {maps.sheenRoughnessTexture, maps.sheenRoughnessChannel, maps.sheenRoughnessUv});
    if (maps.sheenColorTexture >= 0 && texturedMesh(scene, hit))
        layers.sheenColour =
            layers.sheenColour * mapColour(scene, maps.sheenColorTexture, maps.sheenColorUv,
                                           MeshPoint::of(hit), worldWidth);
    return layers;
}

bool normalMapAt(const Scene& scene, const Material& material, const Hit& hit, float worldWidth,
                 Vec3& tangentNormal) {
    const MaterialMaps& maps = material.maps;
    if (maps.normalTexture < 0 || !texturedMesh(scene, hit)) return false;
    if (scene.meshes[hit.shape].tangents.empty()) return false;
    Color texel =
        mapColour(scene, maps.normalTexture, maps.normalUv, MeshPoint::of(hit), worldWidth);
    tangentNormal = Vec3((2 * texel.x - 1) * maps.normalScale, (2 * texel.y - 1) * maps.normalScale,
                         2 * texel.z - 1);
    return true;
}

Color emissionTexelAt(const Scene& scene, const Material& material, const MeshPoint& at) {
    const MaterialMaps& maps = material.maps;
    if (maps.emissionTexture < 0 || !scene.textures || at.mesh >= scene.meshes.size())
        return Color(1.0f);
    if (scene.meshes[at.mesh].uvs.empty()) return Color(1.0f);
    return mapColour(scene, maps.emissionTexture, maps.emissionUv, at, 0.0f);
}

bool hasEmissionTexture(const Scene& scene, uint32_t mesh) {
    const TriangleMesh& m = scene.meshes[mesh];
    if (m.uvs.empty() || !scene.textures) return false;
    return std::any_of(m.materialIds.begin(), m.materialIds.end(), [&](uint32_t id) {
        return id < scene.materials.size() && scene.materials[id].maps.emissionTexture >= 0;
    });
}

float alphaAt(const Scene& scene, const Material& material, const MeshPoint& at) {
    const MaterialMaps& maps = material.maps;
    float alpha = maps.opacity;
    if (maps.opacityTexture >= 0 && scene.textures && !scene.meshes[at.mesh].uvs.empty())
        alpha *=
            mapChannel(scene, maps.opacityTexture, maps.opacityChannel, maps.opacityUv, at, 0.0f);
    return alpha;
}

}  // namespace kiln
