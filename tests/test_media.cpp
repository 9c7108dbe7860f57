// Participating media: the Henyey-Greenstein phase function and free-flight distances against their
// densities (chi-square), Beer-Lambert through a slab, a white furnace with a scattering sphere, a
// sphere's albedo against an analog random walk written here independently, the .kiln reader and
// the render plan. Tolerances are 5 standard errors of the estimators' own variance.
#include <cmath>

#include "chi2.h"
#include "integrators/media.h"
#include "integrators/medium.h"
#include "integrators/path.h"
#include "integrators/render_plan.h"
#include "renderer/accel/accelerator.h"
#include "scene/scene_loader.h"
#include "scene/volume_media.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(Media, HenyeyGreensteinSamplingMatchesItsDensity) {
    const Vec3 forward = normalize(Vec3(0.3f, -0.5f, 0.8f));
    for (float g : {-0.7f, 0.0f, 0.3f, 0.9f}) {
        auto sample = [&](Sampler& s) -> std::optional<Vec3> {
            float u1 = s.next1D(), u2 = s.next1D();
            return sampleHenyeyGreenstein(forward, g, u1, u2);
        };
        auto pdf = [&](const Vec3& w) { return double(henyeyGreenstein(dot(forward, w), g)); };
        test::Chi2Result r = test::chi2Directions(sample, pdf, 400000, 29);
        EXPECT_GT(r.pValue, 1e-4) << "g " << g << ": " << r.table;
    }
}

TEST(Media, PhaseAsBsdfAgreesWithThePhaseFunction) {
    // The vertex stages multiply eval by |cos|: what they see must be the phase function.
    PhaseAsBsdf phase(0.6f);
    const Vec3 wo = normalize(Vec3(0.2f, 0.1f, 1.0f));
    Sampler s(5, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        BsdfSample bs;
        float u1 = s.next1D(), u2 = s.next1D();
        ASSERT_TRUE(phase.sample(wo, 0.5f, u1, u2, bs));
        float p = henyeyGreenstein(dot(-wo, bs.wi), 0.6f);
        EXPECT_NEAR(bs.pdf, p, 1e-5f * p);
        EXPECT_NEAR(bs.f.x * std::abs(bs.wi.z), p, 1e-4f * p);
        EXPECT_NEAR(phase.eval(wo, bs.wi).x * std::abs(bs.wi.z), p, 1e-4f * p);
        EXPECT_EQ(bs.transmission, bs.wi.z < 0);
    }
}

// Distances drawn by the spectral free flight: histogram against the channel mixture's density,
// the segment's end a bin of its own.
TEST(Media, FreeFlightDistancesMatchTheChannelMixture) {
    const HomogeneousMedium m(Color(0.2f, 0.5f, 1.0f), Color(1.0f, 0.6f, 0.3f), 0);
    const Color beta(1.0f, 0.5f, 0.25f);
    const float tMax = 2.0f;
    const Color pmf = m.channelPmf(beta);
    constexpr int kBins = 60, kSamples = 400000;
    std::vector<double> observed(kBins + 1, 0), expected(kBins + 1, 0);
    Sampler s(11, 0, 0);
    for (int i = 0; i < kSamples; ++i) {
        float uc = s.next1D(), ud = s.next1D();
        FreeFlight f = m.sample(tMax, beta, uc, ud);
        observed[f.scattered ? std::min(kBins - 1, int(f.t / tMax * kBins)) : kBins] += 1;
    }
    auto cdf = [&](double t) {  // probability of scattering before t (t <= tMax)
        double c = 0;
        for (int k = 0; k < 3; ++k) c += pmf[k] * (1 - std::exp(-double(m.sigmaT()[k]) * t));
        return c;
    };
    for (int b = 0; b < kBins; ++b)
        expected[size_t(b)] = kSamples * (cdf((b + 1) * tMax / kBins) - cdf(b * tMax / kBins));
    expected[kBins] = kSamples * (1 - cdf(tMax));
    test::Chi2Result r = test::chi2FromCounts(observed, expected);
    EXPECT_GT(r.pValue, 1e-4) << r.table;
}

// The weights make the estimator unbiased: passing the segment averages to its transmittance, and
// the scattering weight to the probability of scattering times the albedo, per channel.
TEST(Media, FreeFlightWeightsAreUnbiased) {
    const HomogeneousMedium m(Color(0.2f, 0.5f, 1.0f), Color(1.0f, 0.6f, 0.3f), 0);
    const Color beta(0.3f, 1.0f, 0.6f);
    const float tMax = 1.5f;
    constexpr int kSamples = 200000;
    double pass[3] = {}, pass2[3] = {}, scatter[3] = {}, scatter2[3] = {};
    Sampler s(13, 0, 0);
    for (int i = 0; i < kSamples; ++i) {
        float uc = s.next1D(), ud = s.next1D();
        FreeFlight f = m.sample(tMax, beta, uc, ud);
        for (int k = 0; k < 3; ++k) {
            double w = f.weight[k];
            (f.scattered ? scatter : pass)[k] += w;
            (f.scattered ? scatter2 : pass2)[k] += w * w;
        }
    }
    for (int k = 0; k < 3; ++k) {
        double tr = std::exp(-double(m.sigmaT()[k]) * tMax);
        double albedo = double(m.sigmaS()[k]) / m.sigmaT()[k];
        auto check = [&](double sum, double sum2, double expect, const char* what) {
            double mean = sum / kSamples;
            double se = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
            EXPECT_NEAR(mean, expect, 5 * se + 1e-7) << what << " channel " << k;
        };
        check(pass[k], pass2[k], tr, "transmittance");
        check(scatter[k], scatter2[k], albedo * (1 - tr), "scattering");
    }
}

// A closed box [lo, hi], wound outwards (12 triangles).
TriangleMesh box(const Vec3& lo, const Vec3& hi) {
    TriangleMesh m;
    m.name = "box";
    for (int i = 0; i < 8; ++i)
        m.positions.insert(m.positions.end(),
                           {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    m.materialIds = {0};
    m.finalizePadding();
    return m;
}

// A unit sphere of medium behind an index-matched (lambertian-material) boundary.
Scene mediumSphere(const Medium& medium, bool insideOut = false) {
    TriangleMesh sphere = test::sphereMesh(48, 96);  // wound inwards: SceneMedia copes
    if (insideOut)
        for (size_t t = 0; t < sphere.triangleCount(); ++t)
            std::swap(sphere.indices[3 * t + 1], sphere.indices[3 * t + 2]);
    sphere.interior = 0;
    Scene s = test::sceneWith(sphere);
    s.media.push_back(medium);
    s.lights.push_back(test::uniformEnvironment());
    s.camera.position = Vec3(0, 0, 4);
    s.camera.hFovDeg = s.camera.vFovDeg = 35;
    return s;
}

TEST(Media, BoxMeshIsWoundOutwards) {
    // The slab tests below rely on the box's winding; the signed volume says which way it is.
    TriangleMesh b = box(Vec3(0.0f), Vec3(1.0f));
    double v = 0;
    for (size_t t = 0; t < b.triangleCount(); ++t)
        v += dot(Vec3d(b.vertex(b.indices[3 * t])), cross(Vec3d(b.vertex(b.indices[3 * t + 1])),
                                                          Vec3d(b.vertex(b.indices[3 * t + 2]))));
    EXPECT_NEAR(v, 6.0, 1e-9);
}

TEST(Media, ShadowRayThroughASlabIsBeerLambert) {
    TriangleMesh slab = box(Vec3(-5, -5, 0), Vec3(5, 5, 0.5f));
    slab.interior = 0;
    Scene s = test::sceneWith(slab);
    s.media.push_back(Medium{"ink", Color(0.4f, 1.0f, 2.0f), Color(0.0f), 0});
    auto accel = makeEmbreeAccelerator(s);
    SceneMedia media(s);
    uint64_t rays = 0;
    for (float cosTheta : {1.0f, 0.7f, 0.3f}) {
        Vec3 d(std::sqrt(1 - cosTheta * cosTheta), 0, cosTheta);
        // From below the slab to a point above it, and to infinity.
        Ray toPoint{Vec3(0.13f, 0.07f, -1), 0, d * (3 / cosTheta), 1.0f};
        Ray toInfinity{Vec3(0.13f, 0.07f, -1), 0, d, kInfinity};
        for (const Ray& r : {toPoint, toInfinity}) {
            Color tr = media.transmittance(*accel, r, -1, rays);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(tr[k], std::exp(-s.media[0].sigmaA[k] * 0.5f / cosTheta), 1e-4f)
                    << cosTheta;
        }
    }
    // A shadow ray that starts inside the slab collects only the part inside.
    Ray fromInside{Vec3(0.13f, 0.07f, 0.25f), 0, Vec3(0, 0, 2), 1.0f};
    EXPECT_NEAR(media.transmittance(*accel, fromInside, 0, rays).x, std::exp(-0.4f * 0.25f), 1e-4f);
    // Any other surface blocks it.
    s.materials[0].kind = MaterialKind::Glass;
    SceneMedia glass(s);
    EXPECT_EQ(maxComponent(glass.transmittance(*accel, Ray{Vec3(0, 0, -1), 0, Vec3(0, 0, 3), 1.0f},
                                               -1, rays)),
              0.0f);
}

struct Estimate {
    double mean = 0, stderror = 0;
};

// The radiance one ray brings back, averaged over n samples of the integrator the plan builds.
Estimate radianceAlong(const Scene& s, const Ray& ray, int n, int maxDepth) {
    auto accel = makeEmbreeAccelerator(s);
    PathOptions opt;
    opt.maxDepth = maxDepth;
    RenderPlan plan = planFor(s, *accel, {});
    EXPECT_TRUE(plan.media);
    PathIntegrator integrator(s, *accel, opt, plan);
    double sum = 0, sum2 = 0;
    RayCounter counter;
    for (int i = 0; i < n; ++i) {
        Sampler sampler(3, 0, uint64_t(i));
        SampleRecord r;
        integrator.Li(ray, sampler, counter, r);
        sum += r.L.x, sum2 += double(r.L.x) * r.L.x;
    }
    Estimate e;
    e.mean = sum / n;
    e.stderror = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
    return e;
}

// The second method: an analog walk (no next-event estimation, absorption by roulette on the
// albedo) through the same mesh, under the uniform environment of radiance 1, so a walk that
// leaves the sphere scores 1.
Estimate analogWalk(const Scene& s, const Ray& ray, int n) {
    auto accel = makeEmbreeAccelerator(s);
    const Medium& m = s.media[0];
    const float sigmaT = m.sigmaA.x + m.sigmaS.x, albedo = m.sigmaS.x / sigmaT;
    Hit first;
    EXPECT_TRUE(accel->intersect(ray, first));
    const Vec3 entry = ray.origin + ray.dir * first.t;
    Sampler sampler(19, 0, 0);
    int escaped = 0;
    for (int i = 0; i < n; ++i) {
        Vec3 p = entry, d = normalize(ray.dir);
        for (;;) {
            Hit exit;
            if (!accel->intersect(Ray{p, 1e-4f, d, kInfinity}, exit)) break;  // numerically out
            float step = -std::log1p(-sampler.next1D()) / sigmaT;
            if (step >= exit.t) {
                ++escaped;
                break;
            }
            p = p + d * step;
            if (sampler.next1D() >= albedo) break;  // absorbed
            d = sampleHenyeyGreenstein(d, m.g, sampler.next1D(), sampler.next1D());
        }
    }
    Estimate e;
    e.mean = double(escaped) / n;
    e.stderror = std::sqrt(e.mean * (1 - e.mean) / n);
    return e;
}

TEST(Media, ScatteringSphereMatchesAnAnalogWalk) {
    Scene s = mediumSphere(Medium{"milk", Color(0.3f), Color(0.9f), 0.5f});
    for (Vec3 aim : {Vec3(0.0f), Vec3(0.6f, 0.3f, 0)}) {
        Ray ray{Vec3(0, 0, 4), 0, normalize(aim - Vec3(0, 0, 4)), kInfinity};
        Estimate path = radianceAlong(s, ray, 20000, 1000);
        Estimate walk = analogWalk(s, ray, 40000);
        double bound = 5 * std::sqrt(path.stderror * path.stderror + walk.stderror * walk.stderror);
        EXPECT_NEAR(path.mean, walk.mean, bound) << path.mean << " vs " << walk.mean;
        EXPECT_GT(path.mean, 0.2);  // light does come back: a real comparison
        EXPECT_LT(path.mean, 0.9);
    }
}

TEST(Media, WhiteFurnaceScatteringSphereIsInvisible) {
    // Albedo 1 behind an index-matched boundary in a uniform environment: every pixel is 1, also
    // with the sphere wound inside out.
    for (bool insideOut : {false, true}) {
        Scene s = mediumSphere(Medium{"cloud", Color(0.0f), Color(2.0f), 0.4f}, insideOut);
        auto accel = makeEmbreeAccelerator(s);
        RenderJobOptions o = test::jobOptions(16, 16, 32);
        o.path.maxDepth = 1000;
        Film f = test::renderJob(s, *accel, o);
        double sum = 0, var = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                double n = f.samples(x, y), s1 = f.luminanceSum(x, y),
                       s2 = f.luminanceSquareSum(x, y);
                sum += s1 / n;
                var += std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)) / n;
            }
        double mean = sum / 256, se = std::sqrt(var) / 256;
        EXPECT_NEAR(mean, 1.0, 5 * se + 1e-5) << insideOut;
        EXPECT_GT(se, 0.0);  // the sphere scatters: a zero-variance image would prove nothing
    }
}

TEST(Media, AbsorbingSlabDimsTheEnvironmentByBeerLambert) {
    // A camera looking through a slab of ink: each channel arrives as exp(-sigma_a thickness).
    TriangleMesh slab = box(Vec3(-50, -50, -0.5f), Vec3(50, 50, 0.5f));
    slab.interior = 0;
    Scene s = test::sceneWith(slab);
    s.media.push_back(Medium{"ink", Color(0.2f, 0.7f, 1.5f), Color(0.0f), 0});
    s.lights.push_back(test::uniformEnvironment());
    s.camera.position = Vec3(0, 0, 4);
    s.camera.hFovDeg = s.camera.vFovDeg = 1;  // nearly parallel rays: thickness 1
    auto accel = makeEmbreeAccelerator(s);
    Film f = test::renderJob(s, *accel, test::jobOptions(4, 4, 4));
    Color p = f.pixel(2, 2);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], std::exp(-s.media[0].sigmaA[k]), 2e-4f) << k;
}

// A clear principled dielectric (roughness 0, ior 1.5) with KHR_materials_volume's attenuation.
Material absorbingGlass(const Color& attenuation, float distance) {
    Material m{"glass"};
    m.kind = MaterialKind::Principled;
    m.albedo = Color(1.0f);
    m.roughness = 0, m.ior = 1.5f, m.transmission = 1, m.thickness = 1;
    m.attenuationColor = attenuation, m.attenuationDistance = distance;
    return m;
}

TEST(Media, TransmissiveVolumesGetAnAbsorbingInterior) {
    Scene s = test::sceneWith(box(Vec3(0.0f), Vec3(1.0f)));
    const Color c(0.8f, 0.5f, 0.2f);
    s.materials[0] = absorbingGlass(c, 2);
    Material thin = absorbingGlass(c, 2), opaque = absorbingGlass(c, 2);
    thin.thickness = 0, opaque.transmission = 0;
    s.materials.push_back(thin), s.materials.push_back(opaque);
    for (uint32_t m : {1u, 2u, 0u}) {
        s.meshes.push_back(box(Vec3(2.0f), Vec3(3.0f)));
        s.meshes.back().materialIds = {m};
    }
    s.media.push_back(Medium{"ink", Color(1.0f), Color(0.0f), 0});
    s.meshes.back().interior = 0;  // a mesh naming its interior keeps it
    addVolumeMedia(s);
    ASSERT_EQ(s.media.size(), 2u);
    EXPECT_EQ(s.meshes[0].interior, 1);
    EXPECT_EQ(s.meshes[1].interior, -1);  // thin-walled
    EXPECT_EQ(s.meshes[2].interior, -1);  // no transmission
    EXPECT_EQ(s.meshes[3].interior, 0);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(s.media[1].sigmaA[k], -std::log(c[k]) / 2) << k;
    EXPECT_EQ(s.media[1].sigmaS, Color(0.0f));
}

TEST(Media, PrincipledGlassSlabAbsorbsByBeerLambert) {
    // Normal view through a slab of thickness 1 under a uniform sky: Fresnel F = F0 = 0.04 at
    // both faces, t = attenuation colour per pass, so the pixel is what the slab reflects plus what
    // it transmits, summed over the internal reflections: F + (1 - F)^2 (F t^2 + t) / (1 - F^2
    // t^2).
    TriangleMesh slab = box(Vec3(-50, -50, -0.5f), Vec3(50, 50, 0.5f));
    Scene s = test::sceneWith(slab);
    const Color c(0.8f, 0.5f, 0.2f);
    s.materials[0] = absorbingGlass(c, 1);
    addVolumeMedia(s);
    ASSERT_EQ(s.meshes[0].interior, 0);
    s.lights.push_back(test::uniformEnvironment());
    s.camera.position = Vec3(0, 0, 4);
    s.camera.hFovDeg = s.camera.vFovDeg = 1;
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = test::jobOptions(16, 16, 64);
    o.path.maxDepth = 100;
    Film f = test::renderJob(s, *accel, o);
    const double F = 0.04;
    for (int k = 0; k < 3; ++k) {
        // Every pixel estimates the same value: the spread of their means is the standard error.
        double sum = 0, sum2 = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                double p = f.pixel(x, y)[k];
                sum += p, sum2 += p * p;
            }
        double mean = sum / 256, se = std::sqrt(std::max(0.0, sum2 / 256 - mean * mean) / 255);
        double t = c[k];
        double expect = F + (1 - F) * (1 - F) * (F * t * t + t) / (1 - F * F * t * t);
        EXPECT_NEAR(mean, expect, 5 * se + 2e-3) << "channel " << k;
        EXPECT_LT(mean, F + (1 - F) * (1 - F) * (F + 1) / (1 - F * F) - 0.05);  // it absorbs
    }
}

TEST(Media, KilnFileReadsMediaAndPlanNamesThem) {
    auto dir = test::scratchDir() / "media";
    std::filesystem::create_directories(dir);
    test::writeTetrahedronObj(dir / "box.obj");
    std::string scene = test::writeFile(
        dir / "fog.kiln",
        "<kiln-scene><medium name=\"fog\" kind=\"homogeneous\" sigma-a=\"0.1 0.2 0.3\" "
        "sigma-s=\"1 1 1\" g=\"0.3\"/><mesh file=\"box.obj\" interior=\"fog\"/>"
        "<light kind=\"ambient\" radiance=\"1 1 1\"/></kiln-scene>");
    Scene s = loadScene(scene);
    ASSERT_EQ(s.media.size(), 1u);
    EXPECT_EQ(s.media[0].name, "fog");
    EXPECT_FLOAT_EQ(s.media[0].sigmaA.y, 0.2f);
    EXPECT_FLOAT_EQ(s.media[0].g, 0.3f);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].interior, 0);
    auto accel = makeEmbreeAccelerator(s);
    RenderPlan plan = planFor(s, *accel, {});
    EXPECT_TRUE(plan.media);
    EXPECT_NE(plan.compact().find("media"), std::string::npos);

    auto bad = [&](const std::string& body, const std::string& what) {
        test::expectError(
            test::writeFile(dir / "bad.kiln", "<kiln-scene>" + body + "</kiln-scene>"), what);
    };
    bad("<mesh file=\"box.obj\" interior=\"smoke\"/>", "unknown medium 'smoke'");
    bad("<medium name=\"m\" g=\"1\"/>", "g must be in (-1, 1)");
    bad("<medium name=\"m\" sigma-a=\"-1 0 0\"/>", "sigma-a must be >= 0");
    bad("<medium name=\"m\" kind=\"grid\"/>", "kind 'grid'");
    bad("<medium name=\"m\" sigma=\"1 1 1\"/>", "unknown attribute 'sigma'");
}

TEST(Media, MediaAndWalkImagesDoNotDependOnThreadsOrTiles) {
    for (const char* scene : {"scenes/coloured_glass.kiln", "scenes/lucy_subsurface.kiln"}) {
        Scene s = loadScene(test::repo(scene));
        auto accel = makeEmbreeAccelerator(s);
        RenderJobOptions one = test::jobOptions(24, 24, 4), two = one;
        one.settings.threads = 1, one.settings.tileSize = 8;
        two.settings.threads = 2, two.settings.tileSize = 32;
        Film a = test::renderJob(s, *accel, one), b = test::renderJob(s, *accel, two);
        double total = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                ASSERT_EQ(a.pixel(x, y), b.pixel(x, y)) << scene << " " << x << " " << y;
                total += luminance(a.pixel(x, y));
            }
        EXPECT_GT(total, 0.0) << scene;
    }
}

TEST(Media, ScenesWithoutMediaDoNotNameThem) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RenderPlan plan = planFor(s, *accel, {});
    EXPECT_FALSE(plan.media);
    EXPECT_FALSE(plan.subsurface);
    EXPECT_EQ(plan.compact().find("media"), std::string::npos);
}

}  // namespace
}  // namespace kiln
