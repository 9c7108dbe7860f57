#include "scene/mesh_maps.h"

#include <cmath>

namespace kiln {

std::vector<int*> textureIds(Material& m) {
    MaterialMaps& x = m.maps;
    return {&m.albedoTexture,        &x.normalTexture,
            &x.opacityTexture,       &x.metallicTexture,
            &x.roughnessTexture,     &x.emissionTexture,
            &x.clearcoatTexture,     &x.clearcoatRoughnessTexture,
            &x.transmissionTexture,  &x.sheenColorTexture,
            &x.sheenRoughnessTexture};
}

void uvAt(const TriangleMesh& mesh, uint32_t prim, float b1, float b2, float& u, float& v) {
    const uint32_t* idx = &mesh.indices[3 * size_t(prim)];
    const float* uv = mesh.uvs.data();
    float b0 = 1 - b1 - b2;
    u = uv[2 * idx[0]] * b0 + uv[2 * idx[1]] * b1 + uv[2 * idx[2]] * b2;
    v = uv[2 * idx[0] + 1] * b0 + uv[2 * idx[1] + 1] * b1 + uv[2 * idx[2] + 1] * b2;
}

void computeTangents(TriangleMesh& mesh) {
    size_t n = mesh.vertexCount();
    std::vector<Vec3> tSum(n, Vec3(0.0f)), bSum(n, Vec3(0.0f)), nSum(n, Vec3(0.0f));
    for (size_t tri = 0; tri < mesh.triangleCount(); ++tri) {
        const uint32_t* idx = &mesh.indices[3 * tri];
        Vec3 p0 = mesh.vertex(idx[0]);
        Vec3 e1 = mesh.vertex(idx[1]) - p0, e2 = mesh.vertex(idx[2]) - p0;
        const float* uv = mesh.uvs.data();
        float du1 = uv[2 * idx[1]] - uv[2 * idx[0]], dv1 = uv[2 * idx[1] + 1] - uv[2 * idx[0] + 1];
        float du2 = uv[2 * idx[2]] - uv[2 * idx[0]], dv2 = uv[2 * idx[2] + 1] - uv[2 * idx[0] + 1];
        float det = du1 * dv2 - du2 * dv1;
        Vec3 faceN = cross(e1, e2);
        // dp/du and dp/dv times det: weighted by the triangle's size, signed for mirrored UVs.
        float s = det < 0 ? -1.0f : 1.0f;
        Vec3 t = (e1 * dv2 - e2 * dv1) * s, b = (e2 * du1 - e1 * du2) * s;
        for (int k = 0; k < 3; ++k) {
            if (det != 0) tSum[idx[k]] += t, bSum[idx[k]] += b;
            nSum[idx[k]] += faceN;
        }
    }
    mesh.tangents.resize(4 * n);
    for (size_t v = 0; v < n; ++v) {
        Vec3 nv = mesh.normals.empty()
                      ? nSum[v]
                      : Vec3(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]);
        nv = dot(nv, nv) > 0 ? normalize(nv) : Vec3(0, 0, 1);
        // Gram-Schmidt against the normal; a vertex without UV extent gets any perpendicular.
        Vec3 t = tSum[v] - nv * dot(nv, tSum[v]);
        if (!(dot(t, t) > 0)) {
            Vec3 other;
            orthonormalBasis(nv, t, other);
        }
        t = normalize(t);
        float sign = dot(cross(nv, t), bSum[v]) < 0 ? -1.0f : 1.0f;
        float* out = &mesh.tangents[4 * v];
        out[0] = t.x, out[1] = t.y, out[2] = t.z, out[3] = sign;
    }
}

void addMissingTangents(Scene& scene) {
    for (TriangleMesh& mesh : scene.meshes) {
        bool mapped = false;
        for (uint32_t id : mesh.materialIds)
            mapped = mapped ||
                     (id < scene.materials.size() && scene.materials[id].maps.normalTexture >= 0);
        if (!mapped || !mesh.tangents.empty()) continue;
        if (mesh.uvs.empty()) {
            scene.warnings.push_back("mesh '" + mesh.name +
                                     "' has a normal-mapped material but no UVs: its normal map "
                                     "is dropped");
            continue;
        }
        computeTangents(mesh);
    }
}

}  // namespace kiln
