#include "integrators/emitter_surface.h"

#include <algorithm>
#include <cmath>

#include "renderer/core/warp.h"
#include "renderer/geometry/material_lookup.h"
#include "renderer/geometry/opacity.h"

namespace kiln {

SurfaceEmitter::SurfaceEmitter(const Light& l, const Scene& scene) : l_(l), scene_(&scene) {
    Shape& e = shape_;
    if (l.kind == LightKind::MeshEmitter || l.hasMesh) {
        const TriangleMesh& m = scene.meshes[l.mesh];
        std::vector<float> areas;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            Vec3 a = m.vertex(m.indices[3 * t]), bb = m.vertex(m.indices[3 * t + 1]),
                 c = m.vertex(m.indices[3 * t + 2]);
            e.triangles.insert(e.triangles.end(), {a, bb - a, c - a});
            areas.push_back(0.5f * length(cross(bb - a, c - a)));
            e.area += areas.back();
        }
        e.triangleArea = Distribution1D(areas);
        e.emissionTextured = hasEmissionTexture(scene, l.mesh);
        e.alphaCut = meshHasAlpha(scene, l.mesh);
    } else {
        // The CGL rectangle: two triangles spanning position +- dimX/2 +- dimY/2.
        Vec3 p00 = l.position - l.dimX * 0.5f - l.dimY * 0.5f;
        Vec3 p10 = p00 + l.dimX, p01 = p00 + l.dimY, p11 = p00 + l.dimX + l.dimY;
        e.triangles = {p00, p10 - p00, p11 - p00, p00, p11 - p00, p01 - p00};
        e.area = length(cross(l.dimX, l.dimY));
        e.triangleArea = Distribution1D({0.5f, 0.5f});
    }
    for (size_t t = 0; t < e.triangles.size(); t += 3) {
        Vec3 n = cross(e.triangles[t + 1], e.triangles[t + 2]);
        e.normals.push_back(dot(n, n) > 0 ? normalize(n) : Vec3(0, 1, 0));
    }
    if (!e.emissionTextured && !e.alphaCut) findParallelogram();
    e.oneSided = l.kind == LightKind::Area;
    e.side = normalize(l.direction);
}

// Two triangles that tile a parallelogram (every CS184 area light, most quads) are sampled as one:
// p = origin + u1 edgeX + u2 edgeY, the same uniform density by area without picking a triangle.
void SurfaceEmitter::findParallelogram() {
    Shape& e = shape_;
    if (e.triangles.size() != 6) return;
    Vec3 a[3], b[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = k == 0 ? e.triangles[0] : e.triangles[0] + e.triangles[size_t(k)];
        b[k] = k == 0 ? e.triangles[3] : e.triangles[3] + e.triangles[3 + size_t(k)];
    }
    // The shared diagonal: two corners of a equal to corners of b (up to the rounding of p0 +
    // edge).
    auto near = [](const Vec3& p, const Vec3& q) {
        Vec3 d = abs(p - q), m = max(abs(p), abs(q));
        return d.x <= 4 * gamma(1) * m.x && d.y <= 4 * gamma(1) * m.y && d.z <= 4 * gamma(1) * m.z;
    };
    int sharedA[2], sharedB[2], n = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (near(a[i], b[j]) && n < 2) sharedA[n] = i, sharedB[n] = j, ++n;
    if (n != 2) return;
    Vec3 x = a[3 - sharedA[0] - sharedA[1]], y = b[3 - sharedB[0] - sharedB[1]];
    Vec3 s1 = a[sharedA[0]], s2 = a[sharedA[1]];
    // Opposite corners of a parallelogram sum to the same point.
    Vec3 deviation = abs(x + y - s1 - s2), scale = abs(x) + abs(y) + abs(s1) + abs(s2);
    if (deviation.x > 8 * gamma(1) * scale.x || deviation.y > 8 * gamma(1) * scale.y ||
        deviation.z > 8 * gamma(1) * scale.z)
        return;
    e.parallelogram = true;
    e.origin = x, e.edgeX = s1 - x, e.edgeY = s2 - x;
    e.originError = deviation;  // how far a sampled point may lie from the real triangles
    // Rounding of origin + edgeX u1 + edgeY u2 for any (u1, u2) in [0, 1]^2, and that deviation:
    // one bound for every sampled point.
    e.pointError = (abs(e.origin) + abs(e.edgeX) + abs(e.edgeY)) * gamma(7) + deviation;
}

// Uniform by area. Written for few divisions and branches: this runs -l times at every path vertex.
SurfaceEmitter::SurfacePoint SurfaceEmitter::samplePoint(float u1, float u2) const {
    const Shape& e = shape_;
    if (e.parallelogram)
        return {e.origin + e.edgeX * u1 + e.edgeY * u2, e.pointError, e.normals[0], Color(1.0f)};
    // One number picks the triangle by area and, rescaled within its slice, the point.
    size_t t = 0;
    float v1 = u1;
    if (e.triangleArea.size() > 1) {
        float pdfUnused;
        float x = e.triangleArea.sampleContinuous(u1, pdfUnused, t);
        v1 = std::clamp(x * float(e.triangleArea.size()) - float(t), 0.0f, 1.0f - 1e-7f);
    }
    const Vec3* tri = &e.triangles[3 * t];
    float b1, b2;
    uniformTriangle(v1, u2, b1, b2);
    SurfacePoint out{tri[0] + tri[1] * b1 + tri[2] * b2,
                     // Rounding of p0 + e1 b1 + e2 b2 (pbrt's gamma bound for a barycentric
                     // interpolation).
                     (abs(tri[0]) + abs(tri[1] * b1) + abs(tri[2] * b2)) * gamma(7), e.normals[t],
                     Color(1.0f)};
    const uint32_t mesh = l_.mesh;
    if (e.emissionTextured)  // as a ray hitting this point sees it (path.cpp)
        out.texel = emissionTexelAt(*scene_, scene_->materials[scene_->meshes[mesh].materialOf(t)],
                                    {mesh, uint32_t(t), b1, b2});
    if (e.alphaCut) out.texel *= coverageAt(*scene_, mesh, uint32_t(t), b1, b2);
    return out;
}

bool SurfaceEmitter::sample(const Vec3& ref, float u1, float u2, LightSample& out) const {
    const Shape& e = shape_;
    auto [p, pError, n, texel] = samplePoint(u1, u2);
    Vec3 d = p - ref;
    // A one-sided light sends nothing to points behind (or in) its plane.
    if (e.oneSided && dot(d, e.side) >= 0) return false;
    float dist2 = dot(d, d);
    if (dist2 == 0 || e.area == 0) return false;
    float invDist = 1.0f / std::sqrt(dist2);
    out.wi = d * invDist;
    float cosL = std::abs(dot(n, out.wi));
    if (cosL == 0) return false;
    out.pdf = dist2 / (cosL * e.area);
    out.p = p;
    out.pError = pError;
    out.Li = l_.radiance * texel;
    return maxComponent(out.Li) > 0;
}

bool SurfaceEmitter::sampleEmission(float pmf, float u1, float u2, float uSide, float u3, float u4,
                                    EmissionSample& out) const {
    const Shape& e = shape_;
    if (e.area <= 0) return false;
    SurfacePoint sp = samplePoint(u1, u2);
    // A one-sided light emits along its side; a two-sided one from either, picked evenly.
    Vec3 n = e.oneSided ? (dot(sp.n, e.side) < 0 ? -sp.n : sp.n) : (uSide < 0.5f ? sp.n : -sp.n);
    float sides = e.oneSided ? 1.0f : 2.0f;
    out.from = surfacePoint(sp.p, sp.pError, n);
    out.dir = Frame(n).toWorld(cosineHemisphere(u3, u4));
    // Le cos / (pdf of the point, 1 / area, times the direction's, cos / pi, over the sides).
    out.power = l_.radiance * sp.texel * (e.area * kPi * sides / pmf);
    return maxComponent(out.power) > 0;
}

}  // namespace kiln
