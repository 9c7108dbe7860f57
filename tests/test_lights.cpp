// Light sampling: chi-square of sampled directions against the claimed pdf for every light with
// extent, exact values for delta lights, selection by power.
#include <OpenImageIO/imageio.h>

#include "chi2.h"
#include "integrators/lights.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// Ray from ref along w against a triangle list: the first hit point and its normal.
bool hitTriangles(const std::vector<Vec3>& tris, const Vec3& ref, const Vec3& w, Vec3& x, Vec3& n) {
    float best = kInfinity;
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        Vec3 e1 = tris[t + 1] - tris[t], e2 = tris[t + 2] - tris[t];
        Vec3 p = cross(w, e2);
        float det = dot(e1, p);
        if (det == 0) continue;
        Vec3 tv = ref - tris[t];
        float u = dot(tv, p) / det;
        Vec3 q = cross(tv, e1);
        float v = dot(w, q) / det, d = dot(e2, q) / det;
        if (u < 0 || v < 0 || u + v > 1 || d <= 0 || d >= best) continue;
        best = d;
        x = ref + w * d;
        n = normalize(cross(e1, e2));
    }
    return best < kInfinity;
}

void expectLightMatchesPdf(const LightSet& lights, size_t i, const Vec3& ref,
                           const std::vector<Vec3>& shape, const std::string& what) {
    auto sample = [&](Sampler& s) -> std::optional<Vec3> {
        LightSample ls;
        float u1 = s.next1D(), u2 = s.next1D();
        if (!lights.sample(i, ref, u1, u2, ls)) return std::nullopt;
        return ls.wi;
    };
    auto pdf = [&](const Vec3& w) -> double {
        Vec3 x, n;
        if (!hitTriangles(shape, ref, w, x, n)) return 0.0;
        return lights.pdf(i, ref, w, x, n);
    };
    // The pdf has sharp edges (the light's outline): integrate each bin with 32 x 32 midpoints.
    test::Chi2Result r = test::chi2Directions(sample, pdf, 300000, 23, 80, 160, 32);
    EXPECT_GT(r.pValue, 1e-4) << what << ": " << r.table;
}

TEST(LightSet, EveryEmitterSampledOnlyWhenNoEmitterIsOutsideTheLights) {
    // A diffuse last vertex may skip its continuation only when NEE samples every emitter: the
    // course scenes' lights and kiln's own scenes' mesh emitters are sampled; an emissive analytic
    // sphere is not (a continuation is its only way to be found).
    EXPECT_TRUE(LightSet(loadScene(test::cs184("sky/CBbunny.dae"))).everyEmitterSampled());
    Scene cornell = loadScene(test::repo("scenes/cornell.dae"));
    EXPECT_TRUE(LightSet(cornell).everyEmitterSampled());
    Material glow;
    glow.kind = MaterialKind::Emission;
    glow.emission = Color(3.0f);
    cornell.materials.push_back(glow);
    cornell.spheres.push_back(
        {"glow", Vec3(0, 1, 0), 0.1f, uint32_t(cornell.materials.size() - 1)});
    EXPECT_FALSE(LightSet(cornell).everyEmitterSampled());
}

TEST(LightSampling, RectangleAreaLight) {
    Scene s;
    Light l;
    l.kind = LightKind::Area;
    l.position = Vec3(0.2f, 1, -0.1f);
    l.direction = Vec3(0, -1, 0);
    l.dimX = Vec3(0.6f, 0, 0), l.dimY = Vec3(0, 0, 0.8f);
    l.radiance = Color(10.0f);
    s.lights.push_back(l);
    LightSet lights(s);
    Vec3 c = l.position - l.dimX * 0.5f - l.dimY * 0.5f;
    std::vector<Vec3> rect = {c, c + l.dimX,          c + l.dimX + l.dimY,
                              c, c + l.dimX + l.dimY, c + l.dimY};
    expectLightMatchesPdf(lights, 0, Vec3(0, 0, 0), rect, "rectangle");
    expectLightMatchesPdf(lights, 0, Vec3(1.2f, 0.6f, 0.3f), rect, "rectangle, oblique");
    // One-sided: nothing reaches a point above the light.
    LightSample ls;
    EXPECT_FALSE(lights.sample(0, Vec3(0, 2, 0), 0.3f, 0.6f, ls));
}

// A scene whose only light is one emissive mesh; `tris` gets its triangles as corner lists.
Scene emitterScene(std::vector<float> positions, std::vector<uint32_t> indices,
                   std::vector<Vec3>& tris) {
    TriangleMesh m;
    m.positions = std::move(positions);
    m.indices = std::move(indices);
    m.materialIds = {0};
    m.finalizePadding();
    Scene s = test::sceneWith(m);
    s.materials[0].kind = MaterialKind::Emission;
    s.materials[0].emission = Color(3.0f);
    addEmissiveMeshLights(s);
    EXPECT_EQ(s.lights.size(), 1u);
    for (uint32_t idx : s.meshes[0].indices) tris.push_back(s.meshes[0].vertex(idx));
    return s;
}

TEST(LightSampling, EmissiveMeshByArea) {
    // A planar fan around an off-centre point: triangles of very different areas, picked by area.
    std::vector<Vec3> tris;
    Scene s = emitterScene({0, 0, 0, 2, 0, 0, 2, 0, 1, 0, 0, 1, 0.1f, 0, 0.05f},
                           {4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0}, tris);
    LightSet lights(s);
    expectLightMatchesPdf(lights, 0, Vec3(0.7f, 1.2f, 0.4f), tris, "mesh, from above");
    expectLightMatchesPdf(lights, 0, Vec3(0.7f, -0.5f, 2.0f), tris, "mesh, from below (two-sided)");
}

TEST(LightSampling, TwoTriangleEmittersParallelogramOrNot) {
    // Two triangles: a sheared parallelogram (sampled as one) and a kite of unequal halves (must
    // not be: a parallelogram sample would land outside it and fail the test).
    struct Case {
        std::vector<float> positions;
        const char* what;
    } cases[] = {
        {{0, 0, 0, 2, 0, 0.3f, 2.5f, 0, 1.3f, 0.5f, 0, 1}, "sheared parallelogram"},
        {{0, 0, 0, 2, 0, 0, 2.2f, 0, 1.5f, 0, 0, 0.4f}, "kite"},
    };
    for (const Case& c : cases) {
        std::vector<Vec3> tris;
        Scene s = emitterScene(c.positions, {0, 1, 2, 0, 2, 3}, tris);
        LightSet lights(s);
        expectLightMatchesPdf(lights, 0, Vec3(0.9f, 1.1f, 0.4f), tris, c.what);
    }
}

TEST(LightSampling, AmbientHemisphere) {
    Scene s;
    Light l;
    l.kind = LightKind::Ambient;
    l.radiance = Color(1.0f);
    s.lights.push_back(l);
    LightSet lights(s);
    auto sample = [&](Sampler& smp) -> std::optional<Vec3> {
        LightSample ls;
        float u1 = smp.next1D(), u2 = smp.next1D();
        if (!lights.sample(0, Vec3(0.0f), u1, u2, ls)) return std::nullopt;
        EXPECT_GT(ls.wi.y, 0.0f);
        return ls.wi;
    };
    auto pdf = [&](const Vec3& w) -> double {
        return lights.pdf(0, Vec3(0.0f), w, Vec3(0.0f), Vec3(0.0f));
    };
    test::Chi2Result r = test::chi2Directions(sample, pdf, 300000, 5);
    EXPECT_GT(r.pValue, 1e-4) << r.table;
}

// The environment light as the loader makes it: bilinear lookups through the scene's TextureSet,
// turned by rotationDeg about the up axis. Sampling must match the pdf, and the radiance a sample
// returns must be what a ray escaping that way sees.
// A synthetic 64 x 32 map: a sky gradient, a bright sun and a black band, written as EXR and read
// as the loader reads it, turned by rotationDeg.
void syntheticEnvironment(float rotationDeg, Light& l) {
    constexpr int W = 64, H = 32;
    std::vector<float> px(W * H * 3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float v = 0.1f + float(y) / H;
            if (std::abs(x - 40) <= 1 && std::abs(y - 8) <= 1) v = 500.0f;
            if (y >= 20 && y < 23) v = 0.0f;
            for (int c = 0; c < 3; ++c) px[(y * W + x) * 3 + c] = v * (c == 0 ? 1.0f : 0.7f);
        }
    std::string path = (test::scratchDir() / "env.exr").string();
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << path;
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    l.kind = LightKind::Environment;
    l.environmentPath = path;
    l.environmentImage = std::make_shared<const RgbImage>(readWorkingSpaceImage(path));
    l.environmentRotationDeg = rotationDeg;
    l.environmentBilinear = true;
}

void checkEnvironmentImportance(float rotationDeg, bool compensated = false) {
    Scene s;
    s.lights.emplace_back();
    syntheticEnvironment(rotationDeg, s.lights.back());
    LightSet lights(s, {.misWithBsdf = compensated});
    ASSERT_EQ(lights.anyCompensated(), compensated);
    // Histogram in the map's own spherical coordinates (pole = +Y, phi = 0 at -Z) so bins align
    // with pixels.
    auto toMapFrame = [](const Vec3& d) { return Vec3(-d.z, d.x, d.y); };
    auto fromMapFrame = [](const Vec3& w) { return Vec3(w.y, w.z, -w.x); };
    auto sample = [&](Sampler& smp) -> std::optional<Vec3> {
        LightSample ls;
        float u1 = smp.next1D(), u2 = smp.next1D();
        // A direction drawn where the bilinear lookup is black (next to the black band) is
        // reported as no light, but it was drawn: the density is checked over every draw.
        bool lit = lights.sample(0, Vec3(0.0f), u1, u2, ls);
        if (ls.pdf <= 0) return std::nullopt;
        // The radiance returned is the map's value in that direction, looked up at the (u, v)
        // drawn rather than recovered from the direction: a round trip error of a few float ulps
        // (1e-6 in u or v) moves the lookup 1e-6 x 64 texels, at most 0.03 where the 500 sun meets
        // its neighbours; 0.1 allows three times that.
        if (lit) {
            Color seen = lights.escaped(0, ls.wi, false);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(ls.Li[c], seen[c], 0.1f) << c;
        }
        return toMapFrame(ls.wi);
    };
    auto pdf = [&](const Vec3& w) -> double {
        return lights.pdf(0, Vec3(0.0f), fromMapFrame(w), Vec3(0.0f), Vec3(0.0f));
    };
    // 24 x 24 points a bin for the expected counts: the texels of a map turned by 30 degrees end
    // at thirds of a bin, where 8 x 8 misjudged the sun's edge bins by several percent (chi2 384
    // for 109 degrees of freedom once the sun held all the density).
    test::Chi2Result r = test::chi2Directions(sample, pdf, 400000, 31, 64, 128, 24);
    EXPECT_GT(r.pValue, 1e-4) << r.table;
}

TEST(LightSampling, EnvironmentMapImportance) { checkEnvironmentImportance(0.0f); }
TEST(LightSampling, RotatedEnvironmentMapImportance) { checkEnvironmentImportance(90.0f); }
// Sampled by the light above half the map's mean (for MIS with BSDF sampling): only the sun.
TEST(LightSampling, CompensatedEnvironmentMapImportance) {
    checkEnvironmentImportance(30.0f, true);
}

// Compensation moves the map's density from the even sky to the light above the cut (the sun's
// texels and the bilinear lookup's reach around them), and leaves an even map's density as it was.
TEST(LightSampling, CompensationSamplesOnlyTheLightAboveTheCut) {
    Scene s;
    s.lights.emplace_back();
    syntheticEnvironment(0.0f, s.lights.back());
    LightSet plain(s), compensated(s, {.misWithBsdf = true});
    EnvironmentMap frame;  // the unrotated (u, v) -> direction mapping
    auto texel = [&](int x, int y) { return frame.direction((x + 0.5f) / 64, (y + 0.5f) / 32); };
    auto pdf = [](const LightSet& l, const Vec3& d) { return l.pdf(0, Vec3(0.0f), d, d, d); };
    const Vec3 sun = texel(40, 8), sky = texel(10, 28);
    // The sun held 92 % of the density; now all of it.
    EXPECT_GT(pdf(compensated, sun), 1.05f * pdf(plain, sun));
    EXPECT_GT(pdf(plain, sky), 0.0f);
    EXPECT_EQ(pdf(compensated, sky), 0.0f);

    Scene even;
    even.lights.emplace_back();
    syntheticEnvironment(0.0f, even.lights.back());
    RgbImage flat = *even.lights.back().environmentImage;
    for (Color& c : flat.pixels) c = Color(0.5f);
    even.lights.back().environmentImage = std::make_shared<const RgbImage>(flat);
    LightSet evenPlain(even), evenCompensated(even, {.misWithBsdf = true});
    for (const Vec3& d : {sun, sky, texel(0, 0)})
        EXPECT_EQ(pdf(evenCompensated, d), pdf(evenPlain, d));

    // Only a map with lit texels cut to 0 counts as compensated (the path tracer then keeps MIS
    // at its last vertex): not an even map, nor a uniform environment without an image.
    EXPECT_TRUE(compensated.anyCompensated());
    EXPECT_FALSE(plain.anyCompensated());
    EXPECT_FALSE(evenCompensated.anyCompensated());
    Scene uniform;
    uniform.lights.emplace_back();
    uniform.lights.back().kind = LightKind::Environment;
    uniform.lights.back().radiance = Color(1.0f);
    EXPECT_FALSE(LightSet(uniform, {.misWithBsdf = true}).anyCompensated());
}

// Light sampling is unbiased for the map rays see: the mean of Li / pdf over draws is the integral
// of the escaped radiance over the sphere (a 1024 x 512 midpoint quadrature in (u, v), where
// d(omega) = 2 pi^2 sin(pi v) du dv), within 5 standard errors of the draws' mean.
TEST(LightSampling, EnvironmentSamplesIntegrateTheMap) {
    Scene s;
    s.lights.emplace_back();
    syntheticEnvironment(30.0f, s.lights.back());
    LightSet lights(s);
    EnvironmentMap frame;  // the unrotated (u, v) -> direction mapping; the integral is the same
    double exact = 0;
    constexpr int QU = 1024, QV = 512;
    for (int y = 0; y < QV; ++y)
        for (int x = 0; x < QU; ++x) {
            float u = (float(x) + 0.5f) / QU, v = (float(y) + 0.5f) / QV;
            double L = lights.escaped(0, frame.direction(u, v), false).x;
            exact += L * 2 * M_PI * M_PI * std::sin(M_PI * v) / (double(QU) * QV);
        }
    double sum = 0, sum2 = 0;
    constexpr int kDraws = 400000;
    for (int k = 0; k < kDraws; ++k) {
        Sampler smp(77, uint64_t(k), 0);
        float u1 = smp.next1D(), u2 = smp.next1D();
        LightSample ls;
        double f = lights.sample(0, Vec3(0.0f), u1, u2, ls) ? ls.Li.x / ls.pdf : 0.0;
        sum += f, sum2 += f * f;
    }
    double mean = sum / kDraws, stderr_ = std::sqrt((sum2 / kDraws - mean * mean) / kDraws);
    EXPECT_NEAR(mean, exact, 5 * stderr_) << "standard error " << stderr_;
}

// An escaped ray's radiance and MIS density looked up together (the map coordinates found once,
// or found beforehand with a batch's) are, bit for bit, the two looked up apart, for the
// environment map (turned and not) and for an ambient light.
TEST(LightSampling, EscapedRadianceWithDensityIsBothApart) {
    for (float rotation : {0.0f, 30.0f}) {
        Scene s;
        s.lights.emplace_back();
        syntheticEnvironment(rotation, s.lights.back());
        s.lights.emplace_back();
        s.lights.back().kind = LightKind::Ambient;
        s.lights.back().radiance = Color(0.5f);
        LightSet lights(s);
        const Vec3 ref(0.1f, 0.2f, 0.3f);
        for (int k = 0; k < 2000; ++k) {
            Sampler smp(5, uint64_t(k), 0);
            const Vec3 dir = uniformSphere(smp.next1D(), smp.next1D());
            for (size_t i = 0; i < lights.size(); ++i) {
                float pdf = -1;
                const Color both = lights.escaped(i, ref, dir, false, pdf);
                const Color alone = lights.escaped(i, dir, false);
                for (int c = 0; c < 3; ++c) ASSERT_EQ(both[c], alone[c]) << i << " " << k;
                ASSERT_EQ(pdf, lights.pdf(i, ref, dir, Vec3(0.0f), Vec3(0.0f))) << i << " " << k;
                // The same from the direction's coordinates found beforehand (a batch's rays).
                float pdfAt = -1;
                const Color at = lights.escaped(i, ref, dir, latLong(dir), false, &pdfAt);
                const Color aloneAt = lights.escaped(i, ref, dir, latLong(dir), false, nullptr);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_EQ(at[c], alone[c]) << i << " " << k;
                    ASSERT_EQ(aloneAt[c], alone[c]) << i << " " << k;
                }
                ASSERT_EQ(pdfAt, pdf) << i << " " << k;
            }
        }
    }
}

// An environment sample taken in two steps (located ahead of shading, its radiance read later), or
// in three (its row kept from the prefetch, then the rest located), is, bit for bit, the sample
// taken at once; other lights are not located.
TEST(LightSampling, LocatedEnvironmentSampleIsTheSample) {
    Scene s;
    s.lights.emplace_back();
    syntheticEnvironment(30.0f, s.lights.back());
    s.lights.emplace_back();
    s.lights.back().kind = LightKind::Ambient;
    s.lights.back().radiance = Color(0.5f);
    LightSet lights(s);
    EnvironmentSample point, inParts;
    EXPECT_FALSE(lights.locate(1, 0.3f, 0.6f, point));
    EXPECT_FALSE(lights.pickRow(1, 0.3f, 0.6f, inParts));
    for (int k = 0; k < 4000; ++k) {
        Sampler smp(9, uint64_t(k), 0);
        const float u1 = smp.next1D(), u2 = smp.next1D();
        LightSample once, twice;
        const bool a = lights.sample(0, Vec3(0.0f), u1, u2, once);
        const bool located = lights.locate(0, u1, u2, point);
        const bool b = located && lights.sampleLocated(0, point, twice);
        ASSERT_EQ(a, b) << k;
        // The row kept from the prefetch, then the rest: the same point.
        ASSERT_TRUE(lights.pickRow(0, u1, u2, inParts));
        ASSERT_EQ(lights.locateInRow(0, u1, inParts), located) << k;
        if (!located) continue;
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(once.wi[c], twice.wi[c]) << k;
            ASSERT_EQ(once.Li[c], twice.Li[c]) << k;
            ASSERT_EQ(point.dir[c], inParts.dir[c]) << k;
        }
        ASSERT_EQ(once.pdf, twice.pdf) << k;
        ASSERT_EQ(once.infinite, twice.infinite) << k;
        ASSERT_EQ(point.pdf, inParts.pdf) << k;
        ASSERT_EQ(point.u, inParts.u) << k;
        ASSERT_EQ(point.v, inParts.v) << k;
        ASSERT_EQ(point.iu, inParts.iu) << k;
        ASSERT_EQ(point.iv, inParts.iv) << k;
    }
}

// An 8 x 4 map whose texel (x, y) holds x + 10 y: the lookup is bilinear between texel centres
// (nearest texel would give a step), longitude wraps, and --env-rotate turns it about +Y.
TEST(LightSampling, EnvironmentLookupIsBilinearAndRotates) {
    auto image = std::make_shared<RgbImage>();
    image->width = 8, image->height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) image->pixels.push_back(Color(float(x + 10 * y)));
    auto lightsFor = [&](Scene& s, float rotationDeg) {
        Light l;
        l.kind = LightKind::Environment;
        l.environmentImage = image;
        l.environmentRotationDeg = rotationDeg;
        l.environmentBilinear = true;
        s.lights.push_back(l);
        return LightSet(s);
    };
    Scene plainScene, turnedScene;
    LightSet plain = lightsFor(plainScene, 0.0f), turned = lightsFor(turnedScene, 90.0f);
    EnvironmentMap frame;  // the unrotated (u, v) -> direction mapping
    // Midway between the centres of texels (2, 1) and (3, 1): their mean, 12.5.
    EXPECT_NEAR(plain.escaped(0, frame.direction(3.0f / 8, 1.5f / 4), false).x, 12.5f, 1e-4f);
    // A quarter of the way from (1, 2) to (1, 3) and centred in x: 21 + 2.5.
    EXPECT_NEAR(plain.escaped(0, frame.direction(1.5f / 8, 2.75f / 4), false).x, 23.5f, 1e-4f);
    // Across the seam: between texel 7 and texel 0 of row 0 (wrapping): 3.5.
    EXPECT_NEAR(plain.escaped(0, frame.direction(0.0f, 0.5f / 4), false).x, 3.5f, 1e-4f);
    // Turned 90 degrees: what was seen along d is seen along d turned by 90 degrees about +Y.
    for (float u : {0.1f, 0.37f, 0.8f}) {
        Vec3 d = frame.direction(u, 0.4f);
        float c = 0.0f, sn = 1.0f;  // cos, sin of 90 degrees; counterclockwise from +Y
        Vec3 turnedD(d.x * c + d.z * sn, d.y, -d.x * sn + d.z * c);
        EXPECT_NEAR(turned.escaped(0, turnedD, false).x, plain.escaped(0, d, false).x, 1e-3f)
            << "u " << u;
    }
}

TEST(LightSampling, DeltaLightsAndSelectionByPower) {
    Scene s;
    Light point;
    point.kind = LightKind::Point;
    point.position = Vec3(0, 2, 0);
    point.radiance = Color(3.0f);
    Light spot = point;
    spot.kind = LightKind::Spot;
    spot.direction = Vec3(0, -1, 0);
    spot.spotInnerDeg = 20, spot.spotOuterDeg = 30;
    Light sun;
    sun.kind = LightKind::Directional;
    sun.direction = normalize(Vec3(1, -1, 0));
    sun.radiance = Color(2.0f);
    s.lights = {point, spot, sun};
    LightSet lights(s);
    LightSample ls;
    ASSERT_TRUE(lights.sample(0, Vec3(0, 0, 0), 0.5f, 0.5f, ls));
    EXPECT_TRUE(ls.delta);
    EXPECT_NEAR(ls.Li.x, 3.0f / 4.0f, 1e-6f);  // inverse square
    ASSERT_TRUE(lights.sample(1, Vec3(0, 0, 0), 0.5f, 0.5f, ls));
    EXPECT_NEAR(ls.Li.x, 3.0f / 4.0f, 1e-6f);                       // on the axis: full intensity
    EXPECT_FALSE(lights.sample(1, Vec3(3, 0, 0), 0.5f, 0.5f, ls));  // 56 degrees off axis: dark
    ASSERT_TRUE(lights.sample(2, Vec3(5, 5, 5), 0.5f, 0.5f, ls));
    EXPECT_TRUE(ls.infinite);
    EXPECT_NEAR(ls.wi.x, -std::sqrt(0.5f), 1e-6f);
    EXPECT_TRUE(lights.allDelta());

    Scene two;
    Light a = point, b = point;
    b.radiance = Color(9.0f);
    two.lights = {a, b};
    LightSet pair(two);
    EXPECT_NEAR(pair.selectPmf(0), 0.25f, 1e-6f);
    EXPECT_NEAR(pair.selectPmf(1), 0.75f, 1e-6f);
}

}  // namespace
}  // namespace kiln
