// MIS weights at every bounce: the light reaching the camera after exactly k bounces (--bounce-only
// -m k) is the same whether it is estimated by light sampling alone, BSDF sampling alone, or MIS of
// the two (power and balance heuristics, one and four light samples), on a glossy (microfacet
// copper) bunny lit only by an importance-sampled environment map and on glossy spheres in a box.
// Wrong weights (not summing to one over the strategies, a pdf in the wrong measure) would move
// the MIS mean away from the single-strategy ones.
#include <cmath>
#include <iterator>
#include <vector>

#include "integrators/path.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

struct Estimate {
    double mean = 0, stderror = 0;  // image-mean luminance and its standard error
};

Estimate render(const Scene& s, const Accelerator& accel, const PathOptions& path, int spp) {
    RenderJobOptions o = test::jobOptions(32, 24, spp, path);
    // Independent samples: the pixels' sample variances then give the means' true standard errors
    // (with stratified samples they only bound them).
    o.settings.sampler = SamplerKind::Independent;
    Film f = test::renderJob(s, accel, o);
    Estimate e;
    double var = 0, n = double(f.pixelCount());
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            e.mean += luminance(f.pixel(x, y)) / n;
            var += f.luminanceVariance(x, y) / (n * n);
        }
    e.stderror = std::sqrt(var);
    return e;
}

struct Strategy {
    const char* name;
    DirectSampling sampling;
    bool power;
    int lightSamples;
};
const Strategy kStrategies[] = {{"light", DirectSampling::Light, true, 1},
                                {"bsdf", DirectSampling::Bsdf, true, 1},
                                {"mis power", DirectSampling::Mis, true, 1},
                                {"mis power -l 4", DirectSampling::Mis, true, 4},
                                {"mis balance", DirectSampling::Mis, false, 1}};

// Every strategy's estimate of the light that bounced exactly k times, k = 1..maxBounce, agree
// within 5 standard errors of their difference.
void expectStrategiesAgree(const Scene& s, int maxBounce, int spp) {
    auto accel = makeEmbreeAccelerator(s);
    for (int bounce = 1; bounce <= maxBounce; ++bounce) {
        Estimate e[std::size(kStrategies)];
        for (size_t k = 0; k < std::size(kStrategies); ++k) {
            PathOptions path;
            path.maxDepth = bounce;
            path.accumulateBounces = false;
            path.roulette = Roulette::Off;
            path.sampling = kStrategies[k].sampling;
            path.heuristic = kStrategies[k].power ? MisHeuristic::Power : MisHeuristic::Balance;
            path.lightSamples = kStrategies[k].lightSamples;
            e[k] = render(s, *accel, path, spp);
            ASSERT_GT(e[k].stderror, 0.0) << kStrategies[k].name << " bounce " << bounce;
        }
        // Light that bounced k times is there to find: a wrong weight would show.
        EXPECT_GT(e[2].mean, 10 * e[2].stderror) << "bounce " << bounce;
        for (size_t a = 0; a < std::size(kStrategies); ++a)
            for (size_t b = a + 1; b < std::size(kStrategies); ++b)
                EXPECT_NEAR(e[a].mean, e[b].mean, 5 * std::hypot(e[a].stderror, e[b].stderror))
                    << kStrategies[a].name << " vs " << kStrategies[b].name << ", bounce "
                    << bounce;
    }
}

TEST(Mis, LightBsdfAndMisAgreeOnAGlossyEnvironmentLitMesh) {
    // The environment map importance-sampled (its pdf varies over the sphere): the light sampling
    // pdf in the weights is the map's own.
    LoadOptions load;
    load.environmentMap = test::shared("envmaps/courtyard.exr");
    expectStrategiesAgree(loadScene(test::cs184("sky/bunny_microfacet_cu_unlit.dae"), load), 2, 64);
}

TEST(Mis, LightBsdfAndMisAgreeOnADiffuseEnvironmentLitMesh) {
    // Where the BSDF and the map's pdf overlap most (a diffuse surface): the weights matter most.
    LoadOptions load;
    load.environmentMap = test::shared("envmaps/courtyard.exr");
    // 512 samples: MIS takes its map samples from the compensated map (the light above half its
    // mean, environment_map.cpp), whose dark ground only BSDF sampling finds; a last vertex that
    // took that map's samples alone would lose 8 % of the light of the first bounce, 3 standard
    // errors at 64.
    expectStrategiesAgree(loadScene(test::cs184("sky/bunny_unlit.dae"), load), 2, 512);
}

TEST(Mis, LightBsdfAndMisAgreeAtEveryBounceAmongGlossySpheresInABox) {
    // Glossy metal spheres in a closed box under an area light: light after every bounce.
    expectStrategiesAgree(loadScene(test::cs184("sky/CBspheres_microfacet_al_ag.dae")), 4, 64);
}

TEST(Mis, ADiffuseLastVertexTakesLightSamplingAloneAndTracesNoContinuation) {
    // At the last vertex MIS would weigh what the continuation finds against NEE; on a diffuse
    // surface NEE alone (weight 1) is used and the continuation is not traced: MIS and light
    // sampling then give the same image, bit for bit, with the same rays, for the light of the
    // last bounce (-m 1, and --bounce-only -m 2). The agreement tests above show it unbiased.
    Scene s = loadScene(test::cs184("sky/CBbunny.dae"));
    auto accel = makeEmbreeAccelerator(s);
    for (int depth : {1, 2}) {
        std::vector<Film> images;
        uint64_t rays[2];
        for (int k = 0; k < 2; ++k) {
            PathOptions path;
            path.maxDepth = depth;
            path.accumulateBounces = depth == 1;
            path.sampling = k == 0 ? DirectSampling::Mis : DirectSampling::Light;
            RenderJobOptions o = test::jobOptions(32, 24, 8, path);
            RenderStats stats;
            images.push_back(test::renderJob(s, *accel, o, &stats));
            rays[k] = stats.rays;
        }
        EXPECT_EQ(rays[0], rays[1]) << "-m " << depth;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 32; ++x)
                ASSERT_EQ(images[0].pixel(x, y), images[1].pixel(x, y)) << x << " " << y;
    }
}

}  // namespace
}  // namespace kiln
