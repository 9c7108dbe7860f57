#include "integrators/lights.h"

#include <cmath>
#include <stdexcept>

#include "renderer/core/warp.h"
#include "renderer/geometry/material_lookup.h"
#include "renderer/geometry/opacity.h"
#include "scene/light_kinds.h"

namespace kiln {
namespace {

float spotFalloff(const Light& l, const Vec3& wFromLight) {
    float c = dot(normalize(l.direction), wFromLight);
    float cosOuter = std::cos(radians(l.spotOuterDeg)),
          cosInner = std::cos(radians(l.spotInnerDeg));
    if (c <= cosOuter) return 0;
    if (c >= cosInner) return 1;
    float t = (c - cosOuter) / (cosInner - cosOuter);
    return t * t * (3 - 2 * t);  // smoothstep
}

// Importance of each texel for sampling. A bilinear lookup blends a texel with its neighbours (up
// to one texel away), so each weight is the largest of its 3 x 3 neighbourhood (longitude wraps):
// every direction the lookup lights has a nonzero pdf, as light-only sampling needs.
std::vector<float> samplingWeights(const EnvironmentMap& env) {
    const int w = env.width, h = env.height;
    std::vector<float> own(env.pixels.size()), weight(env.pixels.size());
    for (size_t i = 0; i < own.size(); ++i) own[i] = maxComponent(env.pixels[i]);
    for (int y = 0; y < h; ++y) {
        float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            float m = 0;
            for (int dy = std::max(0, y - 1); dy <= std::min(h - 1, y + 1); ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    m = std::max(m, own[size_t(dy) * w + size_t((x + dx + w) % w)]);
            weight[size_t(y) * w + x] = (env.bilinear ? m : own[size_t(y) * w + x]) * sinTheta;
        }
    }
    return weight;
}

bool emits(const Scene& scene, uint32_t material) {
    return maxComponent(scene.materials[material].emission) > 0;
}

// An emitting surface no light samples: a sphere, an instanced mesh or a mesh bound to no light.
bool hasUnsampledEmitter(const Scene& scene, const std::vector<int>& meshLight) {
    for (const Sphere& s : scene.spheres)
        if (emits(scene, s.material)) return true;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (meshLight[m] >= 0) continue;  // prototypes (instanced meshes) are bound to none
        for (uint32_t id : scene.meshes[m].materialIds)
            if (emits(scene, id)) return true;
    }
    return false;
}

EnvironmentMap loadEnvironment(const Light& l, const Scene& scene) {
    EnvironmentMap env;
    env.scale = l.environmentScale;
    env.rotation = l.environmentRotationDeg * kPi / 180.0f;
    env.bilinear = l.environmentBilinear;
    if (!l.environmentImage) {
        env.constant = l.radiance;
        return env;
    }
    const RgbImage& image = *l.environmentImage;
    env.width = image.width, env.height = image.height;
    env.pixels.resize(size_t(env.width) * env.height);
    for (size_t i = 0; i < env.pixels.size(); ++i) {
        Color c = image.pixels[i] * env.scale;
        if (!isFinite(c)) c = Color(0.0f);
        env.pixels[i] = max(c, Color(0.0f));
    }
    env.distribution = Distribution2D(samplingWeights(env), size_t(env.width), size_t(env.height));
    return env;
}

}  // namespace

// Two triangles that tile a parallelogram (every CS184 area light, most quads) are sampled as one:
// p = origin + u1 edgeX + u2 edgeY, the same uniform density by area without picking a triangle.
void LightSet::findParallelogram(Entry& e) {
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

Vec3 EnvironmentMap::direction(float u, float v) const {
    float phi = (u - 0.5f) * 2 * kPi - rotation, theta = v * kPi;  // phi runs clockwise
    float s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

void EnvironmentMap::coordinates(const Vec3& d, float& u, float& v) const {
    u = 0.5f + std::atan2(d.x, -d.z) / (2 * kPi);
    if (rotation != 0) {
        u += rotation / (2 * kPi);
        u -= std::floor(u);
    }
    v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
    u = std::clamp(u, 0.0f, 1.0f - 1e-7f);
    v = std::clamp(v, 0.0f, 1.0f - 1e-7f);
}

Color EnvironmentMap::lookup(const Vec3& dir) const {
    if (pixels.empty()) return constant;
    float u, v;
    coordinates(dir, u, v);
    if (bilinear) return bilinearLookup(u, v);
    int x = std::min(width - 1, int(u * float(width))),
        y = std::min(height - 1, int(v * float(height)));
    return pixels[size_t(y) * width + x];
}

// Between texel centres of the in-memory map (the one importance sampling reads): u wraps, v
// clamps. The same filter as a TextureSystem bilinear lookup on the finest level, at a small
// fraction of its cost: an escaped ray in an environment-lit scene spent a third of the render in
// OIIO's texture calls.
Color EnvironmentMap::bilinearLookup(float u, float v) const {
    float x = u * float(width) - 0.5f,
          y = std::clamp(v * float(height) - 0.5f, 0.0f, float(height - 1));
    float fx = std::floor(x), fy = std::floor(y);
    float tx = x - fx, ty = y - fy;
    int x0 = int(fx), y0 = int(fy);
    int x1 = x0 + 1, y1 = std::min(y0 + 1, height - 1);
    x0 = (x0 % width + width) % width, x1 = (x1 % width + width) % width;
    auto at = [&](int xx, int yy) { return pixels[size_t(yy) * size_t(width) + size_t(xx)]; };
    return (at(x0, y0) * (1 - tx) + at(x1, y0) * tx) * (1 - ty) +
           (at(x0, y1) * (1 - tx) + at(x1, y1) * tx) * ty;
}

LightSet::LightSet(const Scene& scene) : scene_(&scene) {
    std::vector<bool> proto = scene.prototypeMask();
    meshLight_.assign(scene.meshes.size(), -1);
    Bounds3 b = scene.storedBounds();
    float radius = b.empty() ? 1.0f : 0.5f * length(b.diagonal());
    for (const Light& l : scene.lights) {
        Entry e;
        e.light = &l;
        e.hittable = specOf(l.kind).hittable(l);
        if (l.kind == LightKind::Area || l.kind == LightKind::MeshEmitter) {
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
                if (!proto[l.mesh]) meshLight_[l.mesh] = int(lights_.size());
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
            if (!e.emissionTextured && !e.alphaCut) findParallelogram(e);
            e.oneSided = l.kind == LightKind::Area;
            e.side = normalize(l.direction);
        } else if (l.kind == LightKind::Environment) {
            e.env = loadEnvironment(l, scene);
            infinite_.push_back(lights_.size());
        } else if (l.kind == LightKind::Ambient) {
            infinite_.push_back(lights_.size());
        }
        lights_.push_back(std::move(e));
    }
    everyEmitterSampled_ = !hasUnsampledEmitter(scene, meshLight_);
    std::vector<float> powers, emitterPowers;
    for (size_t i = 0; i < lights_.size(); ++i) {
        powers.push_back(power(lights_[i], radius));
        LightKind k = lights_[i].light->kind;
        if (k == LightKind::Area || k == LightKind::MeshEmitter) {
            surfaceEmitters_.push_back(i);
            emitterPowers.push_back(powers.back());
        }
    }
    power_ = Distribution1D(powers);
    emitterPower_ = Distribution1D(emitterPowers);
}

float LightSet::power(const Entry& e, float r) const {
    const Light& l = *e.light;
    float lum = luminance(l.radiance);
    switch (l.kind) {
        case LightKind::Area:
        case LightKind::MeshEmitter:
            return lum * e.area * kPi * (e.oneSided ? 1.0f : 2.0f);
        case LightKind::Point:
            return 4 * kPi * lum;
        case LightKind::Spot:
            return 2 * kPi * lum *
                   (1 -
                    0.5f * (std::cos(radians(l.spotInnerDeg)) + std::cos(radians(l.spotOuterDeg))));
        case LightKind::Directional:
            return lum * kPi * r * r;
        case LightKind::Ambient:
            return lum * kPi * kPi * r * r;
        case LightKind::Environment: {
            float avg = e.env.pixels.empty() ? luminance(e.env.constant) : 0.0f;
            for (const Color& c : e.env.pixels) avg += luminance(c) / float(e.env.pixels.size());
            return avg * 2 * kPi * kPi * r * r;
        }
    }
    return 0;
}

bool LightSet::hittable(size_t i) const { return lights_[i].hittable; }

bool LightSet::allDelta() const {
    for (const Entry& e : lights_)
        if (!specOf(e.light->kind).delta) return false;
    return true;
}

Color LightSet::emitted(size_t i, const Vec3& x, const Vec3& n, const Vec3& towards) const {
    const Entry& e = lights_[i];
    if (e.oneSided && dot(towards - x, e.side) <= 0) return Color(0.0f);
    return e.light->radiance;
}

// Uniform by area. Written for few divisions and branches: this runs -l times at every path vertex.
LightSet::SurfacePoint LightSet::samplePoint(const Entry& e, float u1, float u2) const {
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
    const uint32_t mesh = e.light->mesh;
    if (e.emissionTextured)  // as a ray hitting this point sees it (path.cpp)
        out.texel = emissionTexelAt(*scene_, scene_->materials[scene_->meshes[mesh].materialOf(t)],
                                    {mesh, uint32_t(t), b1, b2});
    if (e.alphaCut) out.texel *= coverageAt(*scene_, mesh, uint32_t(t), b1, b2);
    return out;
}

bool LightSet::sampleEmission(float uLight, float u1, float u2, float uSide, float u3, float u4,
                              EmissionSample& out) const {
    float pmf;
    size_t i = surfaceEmitters_.empty() ? 0 : emitterPower_.sampleDiscrete(uLight, pmf);
    if (surfaceEmitters_.empty() || pmf <= 0) return false;
    const Entry& e = lights_[surfaceEmitters_[i]];
    if (e.area <= 0) return false;
    SurfacePoint sp = samplePoint(e, u1, u2);
    // A one-sided light emits along its side; a two-sided one from either, picked evenly.
    Vec3 n = e.oneSided ? (dot(sp.n, e.side) < 0 ? -sp.n : sp.n) : (uSide < 0.5f ? sp.n : -sp.n);
    float sides = e.oneSided ? 1.0f : 2.0f;
    out.from = surfacePoint(sp.p, sp.pError, n);
    out.dir = Frame(n).toWorld(cosineHemisphere(u3, u4));
    // Le cos / (pdf of the point, 1 / area, times the direction's, cos / pi, over the sides).
    out.power = e.light->radiance * sp.texel * (e.area * kPi * sides / pmf);
    out.hittable = hittable(surfaceEmitters_[i]);
    return maxComponent(out.power) > 0;
}

bool LightSet::sample(size_t i, const Vec3& ref, float u1, float u2, LightSample& out) const {
    const Entry& e = lights_[i];
    const Light& l = *e.light;
    out = LightSample{};
    switch (l.kind) {
        case LightKind::Area:
        case LightKind::MeshEmitter: {
            auto [p, pError, n, texel] = samplePoint(e, u1, u2);
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
            out.Li = l.radiance * texel;
            return maxComponent(out.Li) > 0;
        }
        case LightKind::Point:
        case LightKind::Spot: {
            Vec3 d = l.position - ref;
            float dist2 = dot(d, d);
            if (dist2 == 0) return false;
            out.wi = d / std::sqrt(dist2);
            out.p = l.position;
            out.pdf = 1;
            out.delta = true;
            out.Li = l.radiance / l.falloffDenominator(dist2);
            if (l.kind == LightKind::Spot) out.Li = out.Li * spotFalloff(l, -out.wi);
            return maxComponent(out.Li) > 0;
        }
        case LightKind::Directional:
            out.wi = -normalize(l.direction);
            out.pdf = 1;
            out.delta = out.infinite = true;
            out.Li = l.radiance;
            return maxComponent(out.Li) > 0;
        case LightKind::Ambient: {
            // Uniform over the upper (+Y) hemisphere, the only part that emits.
            Vec3 w = uniformHemisphere(u1, u2);
            out.wi = Vec3(w.x, w.z, w.y);
            out.pdf = uniformHemispherePdf();
            out.infinite = true;
            out.Li = l.radiance;
            return maxComponent(out.Li) > 0;
        }
        case LightKind::Environment: {
            out.infinite = true;
            if (e.env.pixels.empty()) {
                out.wi = uniformSphere(u1, u2);
                out.pdf = uniformSpherePdf();
                out.Li = e.env.constant;
                return maxComponent(out.Li) > 0;
            }
            float u, v, pdfUV;
            e.env.distribution.sample(u1, u2, u, v, pdfUV);
            float sinTheta = std::sin(v * kPi);
            if (pdfUV == 0 || sinTheta == 0) return false;
            out.wi = e.env.direction(u, v);
            out.pdf = pdfUV / (2 * kPi * kPi * sinTheta);
            out.Li = e.env.lookup(out.wi);
            return maxComponent(out.Li) > 0;
        }
    }
    return false;
}

float LightSet::pdf(size_t i, const Vec3& ref, const Vec3& wi, const Vec3& x, const Vec3& n) const {
    const Entry& e = lights_[i];
    switch (e.light->kind) {
        case LightKind::Area:
        case LightKind::MeshEmitter: {
            Vec3 d = x - ref;
            float cosL = std::abs(dot(n, wi));
            return cosL > 0 && e.area > 0 ? dot(d, d) / (cosL * e.area) : 0.0f;
        }
        case LightKind::Ambient:
            return wi.y > 0 ? uniformHemispherePdf() : 0.0f;
        case LightKind::Environment: {
            if (e.env.pixels.empty()) return uniformSpherePdf();
            float u, v;
            e.env.coordinates(wi, u, v);
            float sinTheta = std::sin(v * kPi);
            return sinTheta > 0 ? e.env.distribution.pdf(u, v) / (2 * kPi * kPi * sinTheta) : 0.0f;
        }
        default:
            return 0.0f;  // delta lights are never hit
    }
}

Color LightSet::escaped(size_t i, const Vec3& dir, bool cameraRay) const {
    const Entry& e = lights_[i];
    if (e.light->kind == LightKind::Environment) return e.env.lookup(dir);
    // The ambient (hemisphere) light lights the scene but is not a visible background, as in CS184.
    if (e.light->kind == LightKind::Ambient && !cameraRay && dir.y > 0) return e.light->radiance;
    return Color(0.0f);
}

}  // namespace kiln
