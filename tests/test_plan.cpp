// The render plan: what each CS184 scene calls for, and the specialised paths giving the general
// path's image.
#include "integrators/path.h"
#include "integrators/render_plan.h"
#include "renderer/render_job.h"
#include "renderer/render_loop.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

struct PlanCase {
    const char* path;
    const char* features;  // RenderPlan::compact() without the closed flag
};

void PrintTo(const PlanCase& c, std::ostream* os) { *os << c.path; }

class Cs184Plan : public ::testing::TestWithParam<PlanCase> {};

TEST_P(Cs184Plan, MatchesWhatTheSceneHolds) {
    Scene s = loadScene(test::cs184(GetParam().path));
    auto accel = makeEmbreeAccelerator(s);
    RenderPlan plan = planFor(s, *accel, AovRequest{});
    std::string compact = plan.compact();
    EXPECT_EQ(compact, GetParam().features) << plan.text();
    EXPECT_FALSE(plan.closed);  // every CS184 scene is open towards its camera
    EXPECT_FALSE(plan.decisions.empty());
}

INSTANTIATE_TEST_SUITE_P(
    Library, Cs184Plan,
    ::testing::Values(
        PlanCase{"keenan/banana.dae", "diffuse-only,infinite-lights"},
        PlanCase{"keenan/building.dae", "diffuse-only,infinite-lights"},
        PlanCase{"meshedit/cow.dae", "diffuse-only,delta-lights-only"},
        PlanCase{"meshedit/maxplanck.dae", "diffuse-only,delta-lights-only"},
        PlanCase{"simple/cube.dae", "diffuse-only,delta-lights-only"},
        PlanCase{"sky/CBbunny.dae", "diffuse-only,area-lights"},
        PlanCase{"sky/CBbunny_microfacet_cu.dae", "rough-conductor,area-lights,guiding"},
        PlanCase{"sky/CBcoil.dae", "delta-specular,area-lights,caustics,guiding"},
        PlanCase{"sky/CBempty.dae", "diffuse-only,area-lights"},
        PlanCase{"sky/CBgems.dae", "delta-specular,transmission,area-lights,caustics"},
        PlanCase{"sky/CBspheres.dae",
                 "delta-specular,transmission,area-lights,spheres,caustics,guiding"},
        PlanCase{"sky/CBspheres_lambertian.dae", "diffuse-only,area-lights,spheres"},
        PlanCase{"sky/CBspheres_microfacet_al_ag.dae",
                 "rough-conductor,area-lights,spheres,guiding"},
        PlanCase{"sky/bunny.dae", "diffuse-only,infinite-lights"},
        PlanCase{"sky/bunny_microfacet_cu.dae", "rough-conductor,infinite-lights"},
        PlanCase{"variants/2018-2020/sky/CBspheres_glossy.dae",
                 "glossy,area-lights,spheres,guiding"},
        PlanCase{"variants/p3-2-sp23/sky/CBspheres_refract.dae",
                 "delta-specular,transmission,area-lights,spheres,caustics"}),
    [](const auto& info) {
        std::string n = info.param.path;
        for (char& c : n)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return n;
    });

Film render(const Scene& s, const Accelerator& accel, const PathOptions& opt, PlanMode mode,
            const AovRequest& aovs = {}, uint64_t* rays = nullptr) {
    RenderJobOptions o = test::jobOptions(40, 30, 8, opt, aovs);
    o.plan = mode;
    RenderStats stats;
    Film film = test::renderJob(s, accel, o, &stats);
    if (rays) *rays = stats.rays;
    return film;
}

TEST(SpecialisedPaths, GiveTheGeneralPathsImage) {
    // Each specialisation removes code that cannot contribute, and draws the same random numbers,
    // so the images are not only statistically equal but identical.
    struct Case {
        const char* scene;
        int depth;
        const char* aovs;
    };
    for (const Case& c :
         {Case{"sky/CBspheres_lambertian.dae", 5, "none"}, Case{"meshedit/cow.dae", 1, "none"},
          Case{"meshedit/cow.dae", 3, "none"}, Case{"sky/bunny.dae", 4, "none"},
          Case{"sky/CBbunny_microfacet_cu.dae", 5, "none"},
          Case{"sky/CBspheres.dae", 5, "default"}}) {
        Scene s = loadScene(test::cs184(c.scene));
        auto accel = makeEmbreeAccelerator(s);
        PathOptions opt;
        opt.maxDepth = c.depth;
        AovRequest aovs = AovRequest::parse(c.aovs, c.depth);
        Film a = render(s, *accel, opt, PlanMode::Auto, aovs),
             b = render(s, *accel, opt, PlanMode::General, aovs);
        double sum = 0;
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x) {
                ASSERT_EQ(a.pixel(x, y), b.pixel(x, y))
                    << c.scene << " -m " << c.depth << " at " << x << "," << y;
                sum += luminance(a.pixel(x, y));
            }
        EXPECT_GT(sum, 0.0) << c.scene;
    }
}

TEST(SpecialisedPaths, DeltaLightsOnlySkipsTheUselessLastRay) {
    // A glossy cow: a diffuse last vertex skips its continuation on every path (light sampling
    // alone), a glossy one only where nothing but delta lights could be found.
    Scene s = loadScene(test::cs184("meshedit/cow.dae"));
    for (Material& m : s.materials) {
        m.kind = MaterialKind::Microfacet;
        m.alpha = 0.3f, m.eta = Color(0.2f), m.k = Color(3.0f);
    }
    auto accel = makeEmbreeAccelerator(s);
    PathOptions opt;
    opt.maxDepth = 1;
    uint64_t special = 0, general = 0;
    render(s, *accel, opt, PlanMode::Auto, {}, &special);
    render(s, *accel, opt, PlanMode::General, {}, &general);
    EXPECT_LT(special,
              general);  // camera + shadow rays only; the general path also traces a continuation
}

// Without -l the plan picks the light samples: 4 where an environment map lights the scene, 1
// elsewhere; -l wins. The job renders with the number it states (the same rays as -l 4).
TEST(PlanLightSamples, FourForAnEnvironmentMapUnlessStated) {
    Scene box = loadScene(test::cs184("sky/CBbunny.dae"));
    auto boxAccel = makeEmbreeAccelerator(box);
    EXPECT_EQ(planFor(box, *boxAccel, AovRequest{}).defaultLightSamples, 1);
    EXPECT_EQ(RenderJob(box, *boxAccel, test::jobOptions(8, 6, 1)).options().path.lightSamples, 1);

    LoadOptions load;
    load.environmentMap = test::shared("envmaps/courtyard.exr");
    Scene lit = loadScene(test::cs184("sky/CBbunny.dae"), load);
    auto accel = makeEmbreeAccelerator(lit);
    RenderPlan plan = planFor(lit, *accel, AovRequest{});
    EXPECT_EQ(plan.defaultLightSamples, RenderPlan::kEnvironmentLightSamples);
    EXPECT_NE(plan.text().find("4 light samples per shading point"), std::string::npos)
        << plan.text();
    RenderJob chosen(lit, *accel, test::jobOptions(16, 12, 2));
    EXPECT_EQ(chosen.options().path.lightSamples, 4);
    PathOptions two;
    two.lightSamples = 2;
    EXPECT_EQ(RenderJob(lit, *accel, test::jobOptions(16, 12, 2, two)).options().path.lightSamples,
              2);
    PathOptions four;
    four.lightSamples = 4;
    RenderStats byPlan, stated;
    Film a = test::renderJob(lit, *accel, test::jobOptions(16, 12, 2), &byPlan);
    Film b = test::renderJob(lit, *accel, test::jobOptions(16, 12, 2, four), &stated);
    EXPECT_EQ(byPlan.rays, stated.rays);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_EQ(a.pixel(x, y), b.pixel(x, y)) << x << " " << y;
}

}  // namespace
}  // namespace kiln
