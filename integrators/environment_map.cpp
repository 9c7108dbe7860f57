#include "integrators/environment_map.h"

#include <algorithm>
#include <cmath>

namespace kiln {
namespace {

float rowSinTheta(int y, int h) { return std::sin(kPi * (float(y) + 0.5f) / float(h)); }

// MIS compensation (Karlik et al. 2019, "MIS compensation: optimizing sampling techniques in
// multiple importance sampling", ACM TOG 38(6)): where BSDF sampling covers every direction and
// MIS weighs the two, the map's samples are better spent on the light standing above its mean
// (the sun, windows), which BSDF sampling rarely finds, than on the even sky it finds anyway. Each
// texel's importance less kCompensation times the solid-angle mean, floored at 0 (an even map
// stays even). A fraction rather than the whole mean because a vertex draws several map samples
// to one BSDF sample (measured: env-lit Lucy under four maps, docs/performance.md).
constexpr double kCompensation = 0.5;

// True where a lit texel was cut to 0: light sampling alone would then miss its light.
bool compensate(std::vector<float>& importance, int w, int h) {
    double sum = 0, solidAngle = 0;
    for (int y = 0; y < h; ++y) {
        const double sinTheta = rowSinTheta(y, h);
        for (int x = 0; x < w; ++x) sum += importance[size_t(y) * w + x] * sinTheta;
        solidAngle += sinTheta * w;
    }
    const float cut = float(kCompensation * sum / solidAngle);
    bool cutAway = false;
    for (float& weight : importance) {
        cutAway |= weight > 0 && weight <= cut;
        weight = std::max(0.0f, weight - cut);
    }
    return cutAway;
}

// Sampling weight of each texel from its importance (own). A bilinear lookup blends a texel with
// its neighbours (up to one texel away), so each weight is the largest of its 3 x 3 neighbourhood
// (longitude wraps): every direction the lookup lights has a nonzero pdf, as light-only sampling
// needs (compensated: every direction the compensated texels light).
std::vector<float> samplingWeights(const EnvironmentMap& env, const std::vector<float>& own) {
    const int w = env.width, h = env.height;
    std::vector<float> weight(env.pixels.size());
    for (int y = 0; y < h; ++y) {
        const float sinTheta = rowSinTheta(y, h);
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

}  // namespace

EnvironmentMap loadEnvironment(const Light& l, bool misCompensated) {
    EnvironmentMap env;
    env.scale = l.environmentScale;
    env.rotation = l.environmentRotationDeg * kPi / 180.0f;
    env.phi =
        AngleTable(-3.14159265358979323846 - double(env.rotation), 2 * 3.14159265358979323846, 256);
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
    std::vector<float> importance(env.pixels.size());
    for (size_t i = 0; i < importance.size(); ++i) importance[i] = maxComponent(env.pixels[i]);
    if (misCompensated) env.compensated = compensate(importance, env.width, env.height);
    env.columns =
        Distribution1DRows(samplingWeights(env, importance), size_t(env.width), size_t(env.height));
    std::vector<float> rowSums(size_t(env.height));
    for (size_t y = 0; y < rowSums.size(); ++y) rowSums[y] = env.columns.integral(y);
    env.rows = Distribution1D(rowSums);
    return env;
}

Vec3 EnvironmentMap::direction(float u, float v) const {
    float sinTheta, cosTheta, sinPhi, cosPhi;  // phi runs clockwise
    theta.sinCos(v, sinTheta, cosTheta);
    phi.sinCos(u, sinPhi, cosPhi);
    return {sinTheta * sinPhi, cosTheta, -sinTheta * cosPhi};
}

void EnvironmentMap::coordinates(const Vec3& d, float& u, float& v) const {
    coordinates(latLong(d), u, v);
}

void EnvironmentMap::coordinates(const LatLong& ll, float& u, float& v) const {
    u = ll.u;
    if (rotation != 0) {
        u += rotation / (2 * kPi);
        u -= std::floor(u);
    }
    u = std::clamp(u, 0.0f, 1.0f - 1e-7f);
    v = std::clamp(ll.v, 0.0f, 1.0f - 1e-7f);
}

// The texel a coordinate in [0, 1) falls in, along an axis of n texels.
static size_t texelOf(float t, int n) { return std::min(size_t(t * float(n)), size_t(n) - 1); }

// A (u, v) density over the unit square as a solid-angle density: the square maps onto the sphere
// with d(omega) = 2 pi^2 sin(theta) du dv.
static float solidAngleDensity(float pdfUV, float sinTheta) {
    return sinTheta > 0 ? pdfUV / (2 * kPi * kPi * sinTheta) : 0.0f;
}

void EnvironmentMap::prefetch(float u1, float u2) const {
    EnvironmentSample row;
    pickRow(u1, u2, row);
}

void EnvironmentMap::pickRow(float u1, float u2, EnvironmentSample& out) const {
    out.v = rows.sampleContinuous(u2, out.pdfV, out.iv);
    columns.prefetch(out.iv, u1);
}

bool EnvironmentMap::locate(float u1, float u2, EnvironmentSample& out) const {
    out.v = rows.sampleContinuous(u2, out.pdfV, out.iv);
    return locateInRow(u1, out);
}

bool EnvironmentMap::locateInRow(float u1, EnvironmentSample& out) const {
    float pdfU;
    const float pdfV = out.pdfV;
    out.u = columns.sampleContinuous(out.iv, u1, pdfU, out.iu);
    float sinTheta, cosTheta, sinPhi, cosPhi;
    theta.sinCos(out.v, sinTheta, cosTheta);
    phi.sinCos(out.u, sinPhi, cosPhi);
    out.dir = {sinTheta * sinPhi, cosTheta, -sinTheta * cosPhi};
    out.pdf = solidAngleDensity(pdfV * pdfU, sinTheta);
    if (out.pdf <= 0) return false;
    prefetchTexels(out.u, out.v, out.iu, out.iv);
    return true;
}

void EnvironmentMap::prefetchTexels(float u, float v, size_t iu, size_t iv) const {
    if (!bilinear) {
        __builtin_prefetch(&pixels[iv * size_t(width) + iu]);
        return;
    }
    const BilinearTexels t = bilinearTexels(u, v);
    for (int y : {t.y0, t.y1})
        for (int x : {t.x0, t.x1})
            __builtin_prefetch(&pixels[size_t(y) * size_t(width) + size_t(x)]);
}

// The radiance where the sample landed, from the (u, v) it was drawn at: no coordinates recovered
// from the direction.
Color EnvironmentMap::radianceAt(const EnvironmentSample& s) const {
    return bilinear ? bilinearLookup(s.u, s.v) : pixels[s.iv * size_t(width) + s.iu];
}

void EnvironmentMap::prefetchLookup(float u, float v) const {
    const size_t iu = texelOf(u, width), iv = texelOf(v, height);
    columns.prefetchDensity(iv, iu);
    prefetchTexels(u, v, iu, iv);
}

float EnvironmentMap::pdf(const Vec3& dir) const {
    float u, v;
    coordinates(dir, u, v);
    return pdf(u, v, dir);
}

float EnvironmentMap::pdf(float u, float v, const Vec3& dir) const {
    const size_t iu = texelOf(u, width), iv = texelOf(v, height);
    const float pdfUV = rows.density(iv) * columns.density(iv, iu);
    return solidAngleDensity(pdfUV, std::sqrt(dir.x * dir.x + dir.z * dir.z));
}

Color EnvironmentMap::lookup(const Vec3& dir) const {
    if (pixels.empty()) return constant;
    float u, v;
    coordinates(dir, u, v);
    return lookup(u, v);
}

Color EnvironmentMap::lookup(float u, float v) const {
    if (bilinear) return bilinearLookup(u, v);
    return pixels[texelOf(v, height) * size_t(width) + texelOf(u, width)];
}
// Between texel centres of the in-memory map (the one importance sampling reads): u wraps, v
// clamps. The same filter as a TextureSystem bilinear lookup on the finest level, at a small
// fraction of its cost: an escaped ray in an environment-lit scene spent a third of the render in
// OIIO's texture calls.
EnvironmentMap::BilinearTexels EnvironmentMap::bilinearTexels(float u, float v) const {
    float x = u * float(width) - 0.5f,
          y = std::clamp(v * float(height) - 0.5f, 0.0f, float(height - 1));
    float fx = std::floor(x), fy = std::floor(y);
    BilinearTexels t;
    t.tx = x - fx, t.ty = y - fy;
    t.x0 = int(fx), t.y0 = int(fy);
    t.x1 = t.x0 + 1, t.y1 = std::min(t.y0 + 1, height - 1);
    // Longitude wraps. u in [0, 1) puts x0 in [-1, width - 1]: one add or subtract (two integer
    // divisions per lookup were a fifth of its cost); any other u by the remainder.
    auto wrap = [&](int xx) {
        if (xx < 0 && xx >= -width) return xx + width;
        if (xx >= width && xx < 2 * width) return xx - width;
        return xx >= 0 && xx < width ? xx : (xx % width + width) % width;
    };
    t.x0 = wrap(t.x0), t.x1 = wrap(t.x1);
    return t;
}

Color EnvironmentMap::bilinearLookup(float u, float v) const {
    const BilinearTexels t = bilinearTexels(u, v);
    const float tx = t.tx, ty = t.ty;
    auto at = [&](int xx, int yy) { return pixels[size_t(yy) * size_t(width) + size_t(xx)]; };
    return (at(t.x0, t.y0) * (1 - tx) + at(t.x1, t.y0) * tx) * (1 - ty) +
           (at(t.x0, t.y1) * (1 - tx) + at(t.x1, t.y1) * tx) * ty;
}

}  // namespace kiln
