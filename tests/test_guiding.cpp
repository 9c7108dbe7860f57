// Caustic guiding (integrators/guiding.h): the guide's sampling matches its density, caustic
// photons land where a mirror sends an area light's light, guided renders converge to the unguided
// image at every bounce, cut the noise of caustics, and stay bit-identical whatever the threads
// and tiles.
#include <cmath>
#include <fstream>

#include "chi2.h"
#include "integrators/guiding.h"
#include "kiln_run.h"
#include "renderer/guide_training.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// Photons landed around the origin on the plane y = 0, from four points above it.
std::vector<GuideRecord> landedAroundOrigin() {
    std::vector<GuideRecord> records;
    const Vec3 sources[] = {{0.5f, 1, 0}, {-0.3f, 0.8f, 0.4f}, {0, 2, -1}, {1, 0.2f, 1}};
    for (int i = 0; i < 32; ++i) {
        Vec3 p(0.01f * float(i % 8) - 0.04f, 0, 0.01f * float(i / 8) - 0.02f);
        records.push_back({p, sources[i % 4], 1.0f + float(i % 3)});
    }
    return records;
}

TEST(GuideLeaf, SamplesMatchTheirDensity) {
    GuideField field(landedAroundOrigin(), 64);
    const Vec3 x(0.01f, 0, 0.005f);
    const GuideLeaf* leaf = field.leafAt(x);
    ASSERT_NE(leaf, nullptr);
    test::Chi2Result r = test::chi2Directions(
        [&](Sampler& s) -> std::optional<Vec3> {
            float u = s.next1D(), u1 = s.next1D(), u2 = s.next1D(), pdf;
            Vec3 d = leaf->sample(x, u, u1, u2, pdf);
            EXPECT_NEAR(pdf, leaf->pdf(x, d), 1e-3f * pdf);
            return d;
        },
        [&](const Vec3& d) { return double(leaf->pdf(x, d)); }, 50000, 7, 80, 160, 32);
    EXPECT_GT(r.pValue, 1e-4) << r.table;
}

TEST(GuideField, GuidesOnlyNearItsPhotonsAndIsTheSameForTheSameRecords) {
    GuideField field(landedAroundOrigin(), 8), again(landedAroundOrigin(), 8);
    EXPECT_EQ(field.stats().leaves, 4u);
    EXPECT_EQ(field.stats().records, 32u);
    EXPECT_NE(field.leafAt(Vec3(0, 0, 0)), nullptr);
    EXPECT_EQ(field.leafAt(Vec3(3, 0, 0)), nullptr);  // far from every landing
    EXPECT_EQ(field.leafAt(Vec3(0, 1, 0)), nullptr);  // off the plane they landed on
    Sampler s(3, 0, 0);
    for (int i = 0; i < 100; ++i) {
        Vec3 x(0.08f * s.next1D() - 0.04f, 0, 0.04f * s.next1D() - 0.02f);
        const GuideLeaf *a = field.leafAt(x), *b = again.leafAt(x);
        ASSERT_EQ(a == nullptr, b == nullptr);
        if (!a) continue;
        float u = s.next1D(), u1 = s.next1D(), u2 = s.next1D(), pa, pb;
        EXPECT_EQ(a->sample(x, u, u1, u2, pa), b->sample(x, u, u1, u2, pb));
        EXPECT_EQ(pa, pb);
    }
}

TEST(GuideField, SplitsPhotonsOnAWallAndTheFloorBesideIt) {
    // Two thirds of the landings on the wall x = -1, a third on the floor y = 0: the median along x
    // lies on the wall's plane, and the split must still cut the wall's photons into small regions
    // (a region of thousands made every guided vertex sum over them all).
    std::vector<GuideRecord> records;
    Sampler s(5, 0, 0);
    for (int i = 0; i < 3000; ++i) {
        float a = 2 * s.next1D(), b = 2 * s.next1D() - 1;
        Vec3 p = i % 3 ? Vec3(-1, a, b) : Vec3(a - 1, 0, b);
        records.push_back({p, Vec3(0, 1, 0), 1});
    }
    GuideField field(records, 32);
    EXPECT_LE(field.stats().largestLeaf, 32u);
    EXPECT_GE(field.stats().leaves, 3000u / 32);
    EXPECT_NE(field.leafAt(Vec3(-1, 1, 0)), nullptr);
    EXPECT_NE(field.leafAt(Vec3(0, 0, 0)), nullptr);
}

// A small emitter at y = 1 (both sides emit), a mirror floor at y = 0 below it and a diffuse
// ceiling at y = 2: the only caustic is light -> mirror -> ceiling.
std::string mirrorScene() {
    auto dir = test::scratchDir();
    auto quad = [&](const char* name, float y, float half) {
        test::writeFile(dir / name, "v " + std::to_string(-half) + " " + std::to_string(y) + " " +
                                        std::to_string(-half) + "\nv " + std::to_string(half) +
                                        " " + std::to_string(y) + " " + std::to_string(-half) +
                                        "\nv " + std::to_string(half) + " " + std::to_string(y) +
                                        " " + std::to_string(half) + "\nv " +
                                        std::to_string(-half) + " " + std::to_string(y) + " " +
                                        std::to_string(half) + "\nf 1 2 3 4\n");
    };
    quad("light.obj", 1, 0.1f);
    quad("mirror.obj", 0, 2);
    quad("ceiling.obj", 2, 4);
    return test::writeFile(dir / "mirror.kiln", R"(<kiln-scene>
  <material name="lamp" kind="lambertian" albedo="0 0 0" emission="10 10 10"/>
  <material name="mirror" kind="mirror" reflectance="1 1 1"/>
  <material name="white" kind="lambertian" albedo="0.5 0.5 0.5"/>
  <mesh file="light.obj" material="lamp"/>
  <mesh file="mirror.obj" material="mirror"/>
  <mesh file="ceiling.obj" material="white"/>
  <camera position="0 1.5 3" look-at="0 1 0" up="0 1 0" fov="60"/>
</kiln-scene>
)");
}

TEST(CausticPhotons, LandWhereTheMirrorSendsTheLight) {
    Scene s = loadScene(mirrorScene());
    auto accel = makeEmbreeAccelerator(s);
    PathIntegrator path(s, *accel, PathOptions{});
    std::vector<GuideRecord> records;
    const size_t photons = 20000;
    path.traceCausticPhotons(0, photons, 11, records);
    // Half the photons leave downwards, nearly all of those reach the mirror and the ceiling.
    EXPECT_GT(records.size(), photons / 4);
    for (const GuideRecord& stored : records) {
        // In world coordinates (the scene stores its points around its own origin).
        GuideRecord r{Vec3(s.world(stored.p)), Vec3(s.world(stored.from)), stored.power};
        ASSERT_NEAR(r.p.y, 2, 1e-4) << "landed on the ceiling";
        ASSERT_NEAR(r.from.y, 0, 1e-4) << "after the mirror, not straight from the light";
        // Unfold the mirror: the photon left the light where the line from the landing point
        // through the mirrored source crosses y = 1.
        Vec3 out = r.p - r.from;
        Vec3 light = r.from - Vec3(out.x, -out.y, out.z) * (1 / out.y);
        EXPECT_LE(std::abs(light.x), 0.1f + 1e-3f);
        EXPECT_LE(std::abs(light.z), 0.1f + 1e-3f);
        EXPECT_GT(r.power, 0);
    }
}

TEST(CausticPhotons, NoneWhereNoCameraPathCouldCarryThemBack) {
    // A mirror sphere under the course's area light, which rays cannot hit: a path from a wall
    // through the mirror can never end on the light (light sampling cannot pass a mirror), so
    // guiding towards the mirror would only waste bounces.
    Scene s = loadScene(test::cs184("variants/p3-2-sp23/sky/CBspheres_refract.dae"));
    auto accel = makeEmbreeAccelerator(s);
    PathIntegrator path(s, *accel, PathOptions{});
    std::vector<GuideRecord> records;
    path.traceCausticPhotons(0, 20000, 11, records);
    EXPECT_TRUE(records.empty()) << records.size();
}

struct Estimate {
    double mean = 0, stderror = 0;  // image-mean luminance and its standard error
    // The pixels' sample variance relative to their brightness (var / (mean^2 + 0.01), the
    // benchmark's relative MSE without a reference), averaged over the image.
    double relativeVariance = 0;
};

Estimate render(const Scene& s, const Accelerator& accel, PathOptions path, GuideMode guiding,
                int spp, int w = 32, int h = 24) {
    path.guiding = guiding;
    RenderJobOptions o = test::jobOptions(w, h, spp, path);
    // Independent samples: the pixels' sample variances then give the means' true standard errors.
    o.settings.sampler = SamplerKind::Independent;
    RenderJob job(s, accel, o);
    Film f = job.makeFilm();
    job.render(f);
    EXPECT_EQ(job.guided(), guiding == GuideMode::On);
    if (guiding == GuideMode::On) {
        EXPECT_NE(job.guidingText().find("landed"), std::string::npos);
    }
    Estimate e;
    double n = double(f.pixelCount()), variance = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            double L = luminance(f.pixel(x, y)), v = f.luminanceVariance(x, y);
            e.mean += L / n;
            variance += v;
            e.relativeVariance += v / (L * L + 0.01) / n;
        }
    e.stderror = std::sqrt(variance) / n;
    return e;
}

// The light that bounced exactly k times, guided and not, agree within 5 standard errors of their
// difference: the mixture's density and the MIS weights are right at every bounce.
void expectGuidedAgrees(const char* scene, int maxBounce, int spp) {
    Scene s = loadScene(test::cs184(scene));
    auto accel = makeEmbreeAccelerator(s);
    for (int bounce = 1; bounce <= maxBounce; ++bounce) {
        PathOptions path;
        path.maxDepth = bounce;
        path.accumulateBounces = false;
        path.roulette = Roulette::Off;
        Estimate on = render(s, *accel, path, GuideMode::On, spp),
                 off = render(s, *accel, path, GuideMode::Off, spp);
        EXPECT_GT(on.mean, 10 * on.stderror) << scene << " bounce " << bounce;
        EXPECT_NEAR(on.mean, off.mean, 5 * std::hypot(on.stderror, off.stderror))
            << scene << " bounce " << bounce;
    }
}

TEST(Guiding, AgreesWithCosineSamplingAtEveryBounceAroundGlassAndMirror) {
    expectGuidedAgrees("sky/CBspheres.dae", 4, 64);
}

TEST(Guiding, AgreesWithCosineSamplingAtEveryBounceAroundGlossyMetal) {
    expectGuidedAgrees("sky/CBspheres_microfacet_al_ag.dae", 3, 64);
}

TEST(Guiding, CutsTheNoiseOfACausticAtEqualSamples) {
    // The copper bunny throws the light's highlight onto the walls and floor.
    Scene s = loadScene(test::cs184("sky/CBbunny_microfacet_cu.dae"));
    auto accel = makeEmbreeAccelerator(s);
    PathOptions path;
    Estimate on = render(s, *accel, path, GuideMode::On, 64, 64, 48),
             off = render(s, *accel, path, GuideMode::Off, 64, 64, 48);
    EXPECT_NEAR(on.mean, off.mean, 5 * std::hypot(on.stderror, off.stderror));
    // The caustic's fireflies sit on the dim walls: relative noise is where guiding shows (the
    // bright copper's own noise, which dominates the plain variance, it leaves alone).
    EXPECT_LT(on.relativeVariance, 0.8 * off.relativeVariance)
        << on.relativeVariance << " against " << off.relativeVariance;
}

TEST(Guiding, BitIdenticalWhateverTheThreadsAndTiles) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions one = test::jobOptions(41, 29, 3);
    one.settings.threads = 1, one.settings.tileSize = 7;
    RenderJobOptions many = one;
    many.settings.threads = 3, many.settings.tileSize = 32;
    RenderJob a(s, *accel, one), b(s, *accel, many);
    ASSERT_TRUE(a.guided());  // the plan's choice for glass and mirror under an area light
    Film fa = a.makeFilm(), fb = b.makeFilm();
    a.render(fa);
    b.render(fb);
    EXPECT_EQ(a.guidingText(), b.guidingText());
    for (int y = 0; y < fa.height(); ++y)
        for (int x = 0; x < fa.width(); ++x)
            ASSERT_EQ(fa.pixel(x, y), fb.pixel(x, y)) << x << "," << y;
}

TEST(Guiding, OnWithHemisphereSamplingIsAOneLineUsageError) {
    std::string out = (test::scratchDir() / "g").string();
    for (const char* bad : {"--guiding on -H", "--guiding on -i normals", "--guiding sometimes"}) {
        test::CliRun r = test::runKiln("render " + test::cs184("sky/CBspheres.dae") +
                                       " -r 8 8 -q -o " + out + " " + bad);
        EXPECT_EQ(r.code, 2) << bad;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find("guiding"), std::string::npos) << r.err;
    }
}

}  // namespace
}  // namespace kiln
