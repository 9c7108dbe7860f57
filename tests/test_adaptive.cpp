// Adaptive sampling by a noise threshold (--noise-threshold T --adaptive-min-spp N): the rule holds
// where a pixel stopped, a flat pixel stops at the first test and a noisy one goes on, the image is
// bit-identical for any threads and tiles and through a refined checkpoint, and the image mean
// stays that of a fixed-spp render within the estimators' standard errors.
#include <cmath>

#include "kiln_run.h"
#include "long_render_support.h"
#include "renderer/adaptive.h"
#include "renderer/long_render.h"

namespace kiln {
namespace {

constexpr float kThreshold = 0.05f;
constexpr int kMinSpp = 8, kMaxSpp = 256, kW = 40, kH = 30;

RenderJobOptions noiseJob(int spp, int threads = 0, int tile = 32, uint64_t seed = 0) {
    RenderJobOptions o = test::jobOptions(kW, kH, spp);
    o.settings.noiseThreshold = kThreshold;
    o.settings.adaptiveMinSpp = kMinSpp;
    o.settings.threads = threads, o.settings.tileSize = tile, o.settings.seed = seed;
    return o;
}

struct Lambertian {
    std::string path = test::cs184("sky/CBspheres_lambertian.dae");
    Scene scene = loadScene(path);
    std::unique_ptr<Accelerator> accel = makeEmbreeAccelerator(scene);
};

TEST(NoiseThreshold, PixelsStopAtTestPointsWhereTheErrorIsBelowTheThreshold) {
    Lambertian l;
    Film film = test::renderJob(l.scene, *l.accel, noiseJob(kMaxSpp));
    int stopped = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            uint32_t n = film.samples(x, y);
            ASSERT_TRUE(n % kMinSpp == 0 && n >= uint32_t(kMinSpp)) << n;
            if (n == uint32_t(kMaxSpp)) continue;
            ++stopped;
            EXPECT_TRUE(film.converged(x, y)) << x << "," << y;
            EXPECT_LE(pixelRelativeError(film, x, y), double(kThreshold)) << x << "," << y;
        }
    EXPECT_GT(stopped, 0);
    EXPECT_LT(uint64_t(stopped), film.pixelCount());  // some pixels needed every sample
}

TEST(NoiseThreshold, AFlatPixelStopsAtTheFirstTestAndANoisyOneDoesNot) {
    // Flat: every sample the same (an emitter seen directly, the black outside): zero variance.
    // Noisy: the largest relative error at kMinSpp in a fixed-spp render of the same samples.
    Lambertian l;
    Film fixed = test::renderJob(l.scene, *l.accel, test::jobOptions(kW, kH, kMinSpp));
    Film adaptive = test::renderJob(l.scene, *l.accel, noiseJob(kMaxSpp));
    int flat = 0, noisyX = 0, noisyY = 0;
    double worst = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            double e = pixelRelativeError(fixed, x, y);
            if (fixed.luminanceVariance(x, y) == 0) {
                ++flat;
                EXPECT_EQ(adaptive.samples(x, y), uint32_t(kMinSpp)) << x << "," << y;
            }
            if (e > worst) worst = e, noisyX = x, noisyY = y;
        }
    EXPECT_GT(flat, 0);
    ASSERT_GT(worst, double(kThreshold));
    // An error e at n samples falls as 1 / sqrt(n): about (e / T)^2 n samples to reach T.
    EXPECT_GT(adaptive.samples(noisyX, noisyY), uint32_t(2 * kMinSpp))
        << noisyX << "," << noisyY << " error " << worst;
}

TEST(NoiseThreshold, IsBitIdenticalForAnyThreadCountAndTileSize) {
    Lambertian l;
    for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
        RenderJobOptions a = noiseJob(128, 2, 32), b = noiseJob(128, 1, 7);
        a.settings.sampler = b.settings.sampler = sampler;
        a.aovs = b.aovs = AovRequest::defaults();
        EXPECT_EQ(test::filmState(test::renderJob(l.scene, *l.accel, a)),
                  test::filmState(test::renderJob(l.scene, *l.accel, b)))
            << toString(sampler);
    }
}

TEST(NoiseThreshold, ARefinedCheckpointGivesTheDirectRender) {
    // The stopping state lives in the film (the converged flags beside the exact sums): a render
    // to 16 spp refined to 128 equals the render to 128, pixel counts included.
    Lambertian l;
    std::string ckpt = (test::scratchDir() / "noise.ckpt").string();
    auto run = [&](int spp, const std::string& path, bool resume) {
        RenderJob job(l.scene, *l.accel, noiseJob(spp));
        LongRenderOptions lo;
        lo.checkpointPath = path;
        lo.resume = resume;
        lo.fingerprint = checkpointFingerprint(job, l.path, {});
        return runLongRender(job, lo);
    };
    run(16, ckpt, false);
    LongRenderResult refined = run(128, ckpt, true);
    EXPECT_TRUE(refined.resumed);
    LongRenderResult direct = run(128, "", false);
    EXPECT_EQ(test::filmState(refined.film), test::filmState(direct.film));
    EXPECT_LT(direct.film.totalSamples(), uint64_t(128) * kW * kH);
}

// Image-mean luminance and its standard error from the pixels' own variances.
std::pair<double, double> imageMean(const Film& f) {
    double mean = 0, var = 0, n = double(f.pixelCount());
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            mean += luminance(f.pixel(x, y)) / n;
            var += f.luminanceVariance(x, y) / (n * n);
        }
    return {mean, std::sqrt(var)};
}

TEST(NoiseThreshold, TheImageMeanAgreesWithAFixedSppRender) {
    // Stopping on a pixel's own samples may bias its mean; at this threshold the bias must stay
    // within the noise: the two means (other seeds, so independent) differ by less than 5
    // standard errors of their difference.
    Lambertian l;
    auto [am, ae] = imageMean(test::renderJob(l.scene, *l.accel, noiseJob(kMaxSpp, 0, 32, 1)));
    auto [fm, fe] = imageMean(test::renderJob(l.scene, *l.accel, test::jobOptions(kW, kH, 64)));
    EXPECT_GT(ae, 0.0);
    EXPECT_NEAR(am, fm, 5.0 * std::sqrt(ae * ae + fe * fe));
}

TEST(NoiseThreshold, TheCommandLineRefusesItWithDashAOrAShardedSampleRange) {
    std::string out = (test::scratchDir() / "n").string();
    std::string base = "render " + test::cs184("sky/CBspheres_lambertian.dae") +
                       " -r 8 8 -s 32 -q -o " + out + " --noise-threshold 0.1";
    test::CliRun both = test::runKiln(base + " -a 8 0.1");
    EXPECT_EQ(both.code, 2);
    EXPECT_NE(both.err.find("-a and --noise-threshold"), std::string::npos) << both.err;
    test::CliRun shard = test::runKiln(base + " --sample-range 16 32");
    EXPECT_EQ(shard.code, 2);
    EXPECT_NE(shard.err.find("--sample-range must start at 0"), std::string::npos) << shard.err;
    test::CliRun bad = test::runKiln(base + " --adaptive-min-spp 1");
    EXPECT_EQ(bad.code, 2);
}

}  // namespace
}  // namespace kiln
