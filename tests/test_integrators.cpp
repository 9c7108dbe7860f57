// Light transport end to end: furnaces with known answers, agreement between estimators that must
// agree, roulette without bias, CS184 depth semantics, adaptive sampling and determinism.
// Tolerances come from the estimator's own sample variance (5 standard errors).
#include "integrators/path.h"
#include "renderer/geometry/camera.h"
#include "renderer/render_loop.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

struct ImageEstimate {
    double mean = 0, stderror = 0;  // image-mean luminance and its standard error
};

ImageEstimate estimate(const Film& film) {
    ImageEstimate e;
    double var = 0;
    int pixels = film.width() * film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            double n = film.samples(x, y), s1 = film.luminanceSum(x, y),
                   s2 = film.luminanceSquareSum(x, y);
            e.mean += s1 / n;
            if (n > 1) var += std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)) / n;
        }
    e.mean /= pixels;
    e.stderror = std::sqrt(var) / pixels;
    return e;
}

Film renderPath(const Scene& s, const PathOptions& opt, RenderSettings settings) {
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = test::jobOptions(settings.width, settings.height, settings.spp, opt);
    o.settings = settings;
    o.settings.progress = false;
    return test::renderJob(s, *accel, o);
}

RenderSettings small(int w, int h, int spp, uint64_t seed = 0) {
    RenderSettings r;
    r.width = w, r.height = h, r.spp = spp, r.seed = seed;
    return r;
}

void expectAgree(const ImageEstimate& a, const ImageEstimate& b, const std::string& what) {
    double bound = 5 * std::sqrt(a.stderror * a.stderror + b.stderror * b.stderror);
    EXPECT_NEAR(a.mean, b.mean, bound) << what << ": " << a.mean << " +- " << a.stderror << " vs "
                                       << b.mean << " +- " << b.stderror;
    EXPECT_GT(bound, 0.0) << what;  // a zero-variance comparison would prove nothing
}

TEST(Furnace, WhiteSphereInAUniformEnvironmentIsInvisible) {
    Scene s;
    s.sourcePath = "furnace";
    Material white;
    white.albedo = Color(1.0f);
    s.materials.push_back(white);
    s.spheres.push_back(Sphere{"ball", Vec3(0.0f), 1.0f, 0});
    Light env;
    env.kind = LightKind::Environment;  // no image: uniform radiance 1
    env.radiance = Color(1.0f);
    s.lights.push_back(env);
    s.camera.position = Vec3(0, 0, 4);
    s.camera.hFovDeg = s.camera.vFovDeg = 35;
    for (DirectSampling sampling :
         {DirectSampling::Mis, DirectSampling::Light, DirectSampling::Hemisphere}) {
        PathOptions opt;
        opt.sampling = sampling;
        opt.maxDepth = 50;
        Film film = renderPath(s, opt, small(24, 24, 64));
        ImageEstimate e = estimate(film);
        EXPECT_NEAR(e.mean, 1.0, 5 * e.stderror + 1e-6) << int(sampling);
        // Every pixel, on the sphere or not, converges to 1: check each against its own error.
        int outliers = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                double n = film.samples(x, y), s1 = film.luminanceSum(x, y),
                       s2 = film.luminanceSquareSum(x, y);
                double sd = std::sqrt(std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)) / n);
                outliers += std::abs(s1 / n - 1.0) > 5 * sd + 1e-5;
            }
        EXPECT_EQ(outliers, 0) << int(sampling);
    }
}

TEST(Furnace, ClosedEmittingBoxGivesOneOverOneMinusAlbedo) {
    for (float albedo : {0.5f, 0.8f}) {
        TriangleMesh shell = test::sphereMesh(24, 48);
        for (float& p : shell.positions) p *= 2;
        Scene s = test::sceneWith(shell);
        s.materials[0].albedo = Color(albedo);
        s.materials[0].emission = Color(1.0f);
        addEmissiveMeshLights(s);
        s.camera.position = Vec3(0.3f, -0.2f, 0.1f);
        s.camera.hFovDeg = s.camera.vFovDeg = 90;
        PathOptions opt;
        opt.maxDepth = 100000;  // unlimited: roulette ends the paths
        Film film = renderPath(s, opt, small(16, 16, 128));
        ImageEstimate e = estimate(film);
        EXPECT_NEAR(e.mean, 1.0 / (1.0 - albedo), 5 * e.stderror)
            << "albedo " << albedo << " +- " << e.stderror;
        EXPECT_GT(e.stderror, 0.0);
    }
}

TEST(DirectLighting, HemisphereLightAndMisAgreeOnCBspheresLambertian) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    ImageEstimate results[3];
    int i = 0;
    for (DirectSampling sampling :
         {DirectSampling::Hemisphere, DirectSampling::Light, DirectSampling::Mis}) {
        PathOptions opt;
        opt.maxDepth = 1;
        opt.sampling = sampling;
        opt.lightSamples = sampling == DirectSampling::Hemisphere ? 1 : 4;
        results[i++] = estimate(
            renderPath(s, opt, small(64, 48, sampling == DirectSampling::Hemisphere ? 512 : 64)));
    }
    expectAgree(results[0], results[1], "hemisphere vs light");
    expectAgree(results[1], results[2], "light vs MIS");
    expectAgree(results[0], results[2], "hemisphere vs MIS");
    // Per camera sample, MIS has a lower variance than hemisphere sampling (512 vs 64 samples were
    // taken).
    EXPECT_LT(results[2].stderror * results[2].stderror * 64,
              results[0].stderror * results[0].stderror * 512);
}

// CS184's -H -l N: N uniform hemisphere rays per shading point. Direct light only (-m 1), so every
// ray past the camera's is a probe: their count grows N-fold and the estimate stays that of light
// sampling.
TEST(DirectLighting, HemisphereTakesLSamplesPerShadingPoint) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    auto accel = makeEmbreeAccelerator(s);
    const int w = 48, h = 36, spp = 64;
    auto render = [&](DirectSampling sampling, int l, RenderStats& stats) {
        PathOptions opt;
        opt.maxDepth = 1;
        opt.sampling = sampling;
        opt.lightSamples = l;
        return estimate(test::renderJob(s, *accel, test::jobOptions(w, h, spp, opt), &stats));
    };
    RenderStats one, sixteen, light;
    ImageEstimate h1 = render(DirectSampling::Hemisphere, 1, one);
    ImageEstimate h16 = render(DirectSampling::Hemisphere, 16, sixteen);
    ImageEstimate l4 = render(DirectSampling::Light, 4, light);
    const double cameraRays = double(w) * h * spp;
    ASSERT_GT(double(one.rays), cameraRays);
    EXPECT_NEAR((double(sixteen.rays) - cameraRays) / (double(one.rays) - cameraRays), 16.0, 0.5);
    expectAgree(h1, h16, "-H -l 1 vs -H -l 16");
    expectAgree(h16, l4, "-H -l 16 vs light sampling");
}

// A grey plane (albedo a) under a uniform sky of radiance 1, direct light only: every pixel is a,
// and one uniform hemisphere probe estimates it as 2 a cos(theta) = 2 a u1, variance a^2 / 3.
// Independent draws: -l N divides that by N. Sobol's split draws (Sampler::split) put one of the N
// probes in each of N strata of u1, each uniform in its stratum: a^2 / (3 N^3).
TEST(DirectLighting, HemisphereProbeVarianceIsAlbedoSquaredOverThreeL) {
    TriangleMesh plane = test::gridMesh(8, 8);
    for (size_t i = 0; i < plane.positions.size(); i += 3)
        plane.positions[i] -= 4, plane.positions[i + 1] -= 4;
    Scene s = test::sceneWith(plane);
    const double albedo = 0.5;
    s.materials[0].albedo = Color(float(albedo));
    Light sky;
    sky.kind = LightKind::Environment;
    sky.radiance = Color(1.0f);
    s.lights.push_back(sky);
    s.camera.position = Vec3(0, 0, 4);
    s.camera.hFovDeg = s.camera.vFovDeg = 30;
    auto accel = makeEmbreeAccelerator(s);
    const int w = 16, h = 16, spp = 32;
    for (SamplerKind kind : {SamplerKind::Independent, SamplerKind::Sobol})
        for (int l : {1, 16}) {
            PathOptions opt;
            opt.maxDepth = 1;
            opt.sampling = DirectSampling::Hemisphere;
            opt.lightSamples = l;
            RenderJobOptions o = test::jobOptions(w, h, spp, opt);
            o.settings.sampler = kind;
            ImageEstimate e = estimate(test::renderJob(s, *accel, o));
            const double samples = double(w) * h * spp,
                         variance = albedo * albedo / 3 /
                                    (kind == SamplerKind::Sobol ? double(l) * l * l : double(l));
            const std::string what = std::string(toString(kind)) + " -l " + std::to_string(l);
            EXPECT_NEAR(e.mean, albedo, 5 * std::sqrt(variance / samples)) << what;
            // The sample variance of 8192 samples is within 10 % of its value.
            EXPECT_NEAR(e.stderror * e.stderror * samples, variance, 0.1 * variance) << what;
        }
}

TEST(RussianRoulette, UnbiasedAgainstNoRoulette) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    ImageEstimate est[3];
    int i = 0;
    for (Roulette rr : {Roulette::Off, Roulette::Throughput, Roulette::Fixed}) {
        PathOptions opt;
        opt.maxDepth = 8;
        opt.roulette = rr;
        est[i++] = estimate(renderPath(s, opt, small(48, 36, 128, 3)));
    }
    expectAgree(est[0], est[1], "off vs throughput");
    expectAgree(est[0], est[2], "off vs fixed 0.65");
}

TEST(Depth, AccumulatedEqualsTheSumOfBouncesAndZeroIsEmissionOnly) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    PathOptions opt;
    opt.maxDepth = 2;
    ImageEstimate total = estimate(renderPath(s, opt, small(48, 36, 64, 1)));
    double sum = 0, var = 0;
    for (int m = 0; m <= 2; ++m) {
        PathOptions only;
        only.maxDepth = m;
        only.accumulateBounces = false;
        ImageEstimate e = estimate(renderPath(s, only, small(48, 36, 64, 10 + m)));
        sum += e.mean;
        var += e.stderror * e.stderror;
    }
    EXPECT_NEAR(total.mean, sum, 5 * std::sqrt(var + total.stderror * total.stderror));
    // -m 0: only emitters are visible, at their radiance (the ceiling light: 10).
    PathOptions zero;
    zero.maxDepth = 0;
    Film film = renderPath(s, zero, small(80, 60, 4));
    int lit = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            Color c = film.pixel(x, y);
            ASSERT_TRUE(c == Color(0.0f) || c.x > 0) << x << "," << y;
            if (film.samples(x, y) && c == Color(10.0f)) ++lit;
        }
    EXPECT_GT(lit, 10);
}

TEST(PathRender, BitIdenticalWhateverTheThreads) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    PathOptions opt;
    RenderSettings a = small(40, 30, 8, 5), b = a;
    a.threads = 1, a.tileSize = 5;
    b.threads = 3, b.tileSize = 16;
    Film fa = renderPath(s, opt, a), fb = renderPath(s, opt, b);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) ASSERT_EQ(fa.pixel(x, y), fb.pixel(x, y)) << x << "," << y;
}

TEST(PathRender, DeltaLightsTakeOneSampleEach) {
    // cow.dae (a directional light) plus two point lights: NEE takes each delta light once
    // (CS184: "a point light gets one sample"), so -l changes neither the image nor the work, and
    // every light is seen at every vertex rather than one picked by power.
    Scene s = loadScene(test::cs184("meshedit/cow.dae"));
    auto addPointLight = [&](const Vec3& position, float radiance) {
        Light point;
        point.kind = LightKind::Point;
        point.position = position;
        point.radiance = Color(radiance);
        s.lights.push_back(point);
    };
    addPointLight(Vec3(-1.0f, 1.0f, 1.0f), 2.0f);
    addPointLight(Vec3(1.5f, 1.0f, 1.0f), 2.0f);
    ASSERT_EQ(s.lights.size(), 3u);
    auto accel = makeEmbreeAccelerator(s);
    auto render = [&](int lightSamples, Film& film) {
        PathOptions opt;
        opt.lightSamples = lightSamples;
        RenderStats stats;
        film = test::renderJob(s, *accel, test::jobOptions(40, 30, 4, opt), &stats);
        return stats;
    };
    Film films[2] = {Film(40, 30), Film(40, 30)};
    RenderStats stats[2] = {render(1, films[0]), render(8, films[1])};
    EXPECT_EQ(stats[0].rays, stats[1].rays);
    int lit = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            ASSERT_EQ(films[0].pixel(x, y), films[1].pixel(x, y)) << x << "," << y;
            lit += maxComponent(films[0].pixel(x, y)) > 0;
        }
    EXPECT_GT(lit, 100);

    // Past 64 delta lights, -l picks by power again: a shadow ray per light per vertex would
    // swamp a many-light scene.
    for (int i = 0; i < 70; ++i) addPointLight(Vec3(-2.0f + 0.05f * float(i), 1.5f, 1.0f), 0.05f);
    Film few(40, 30), many(40, 30);
    // Taking each light once would make the counts equal, whatever -l.
    EXPECT_LT(render(1, few).rays, render(8, many).rays)
        << "-l 8 should trace more shadow rays than -l 1";
}

TEST(PathRender, ABatchTracesEachSampleAsItWouldAlone) {
    // The wavefront traces a batch a bounce at a time, shadow rays queued: every record (beauty and
    // all AOVs) must equal the sample traced on its own, on a scene with glass, a mirror ball, an
    // area light, and paths that end at different depths.
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    PathOptions opt;
    opt.lightSamples = 3;
    AovRequest all = AovRequest::parse("all", 4);
    PathIntegrator integrator(s, *accel, opt, generalPlan(all));
    CameraModel camera(s.camera, 48, 36);
    std::vector<CameraSample> batch;
    for (int i = 0; i < 300; ++i) {
        Sampler sampler(7, uint64_t(i), 0);
        // The centre of the view, where the box is.
        Ray ray = camera.generateRay(float(14 + i % 20) + sampler.next1D(),
                                     float(10 + i / 20) + sampler.next1D());
        batch.push_back({ray, sampler, {}});
        batch.back().record.reset(all);
    }
    std::vector<CameraSample> alone = batch;
    RayCounter batched, single;
    integrator.Li(std::span<CameraSample>(batch), batched);
    for (CameraSample& cs : alone) {
        SampleRecord r;
        r.reset(all);
        integrator.Li(cs.ray, cs.sampler, single, r);
        cs.record = r;
    }
    EXPECT_EQ(batched.rays, single.rays);
    int lit = 0;
    for (size_t i = 0; i < batch.size(); ++i) {
        const SampleRecord &a = batch[i].record, &b = alone[i].record;
        ASSERT_EQ(a.L, b.L) << i;
        ASSERT_EQ(a.direct, b.direct) << i;
        ASSERT_EQ(a.indirect, b.indirect) << i;
        for (int k = 0; k < 4; ++k) ASSERT_EQ(a.bounces[k], b.bounces[k]) << i;
        for (int d = 0; d < 2; ++d)
            for (size_t l = 0; l < kLobeCount; ++l) ASSERT_EQ(a.lobes[d][l], b.lobes[d][l]) << i;
        ASSERT_EQ(a.depth, b.depth) << i;
        lit += maxComponent(a.L) > 0;
    }
    EXPECT_GT(lit, 200);
}

// The frame probe traces many pixels' samples as one batch: each record is the replayed sample.
TEST(PathRender, SamplesOfManyPixelsTracedTogetherAreEachTheReplayedSample) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    PathIntegrator integrator(s, *accel, PathOptions{});
    RenderSettings settings;
    settings.width = 48, settings.height = 36, settings.sampler = SamplerKind::Sobol;
    std::vector<PixelXY> pixels;
    for (int i = 0; i < 40; ++i) pixels.push_back({4 + i % 40, 6 + (i * 7) % 30});
    RayCounter together, alone;
    const int first = 3, count = 5;
    std::vector<SampleRecord> records =
        traceSamples(s, integrator, settings, pixels, first, count, together);
    ASSERT_EQ(records.size(), pixels.size() * count);
    int lit = 0;
    for (size_t p = 0; p < pixels.size(); ++p)
        for (int k = 0; k < count; ++k) {
            SampleRecord r =
                traceSample(s, integrator, settings, pixels[p].x, pixels[p].y, first + k, alone);
            ASSERT_EQ(records[p * count + size_t(k)].L, r.L) << p << " " << k;
            lit += maxComponent(r.L) > 0;
        }
    EXPECT_EQ(together.rays, alone.rays);
    EXPECT_GT(lit, int(pixels.size()));  // not a comparison of black samples
}
TEST(Adaptive, PixelsStopWhenTheCs184ConfidenceTestPasses) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    RenderSettings settings = small(40, 30, 256);
    settings.adaptiveBatch = 16;
    settings.adaptiveTolerance = 0.05f;
    PathOptions opt;
    Film film = renderPath(s, opt, settings);
    uint32_t lo = 1000, hi = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            uint32_t n = film.samples(x, y);
            lo = std::min(lo, n), hi = std::max(hi, n);
            ASSERT_TRUE(n % 16 == 0 || n == 256) << n;
            if (n == 256) continue;
            // Stopped early: the test held at n.
            double s1 = film.luminanceSum(x, y), s2 = film.luminanceSquareSum(x, y);
            double mu = s1 / n, var = std::max(0.0, (s2 - s1 * s1 / n) / (n - 1));
            EXPECT_LE(1.96 * std::sqrt(var / n), 0.05 * mu + 1e-9) << x << "," << y;
        }
    EXPECT_EQ(lo, 16u);  // black background pixels stop after one batch
    EXPECT_GT(hi, 16u);  // noisy pixels keep sampling
}

}  // namespace
}  // namespace kiln
