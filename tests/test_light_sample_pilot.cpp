// The light-sample pilot (renderer/light_sample_pilot.h): where an environment map lights the scene
// and no -l is given, the count follows where the noise comes from (many samples on a diffuse mesh
// lit directly, few on a glossy one), the choice is the same for any region, thread count or
// sample range (so shards and resumed renders agree), -l and area-lit scenes are left alone, and
// the header says what the pilot measured.
#include "renderer/light_sample_pilot.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// The Stanford bunny in MATERIAL, lit only by the courtyard map, filling most of the frame.
Scene bunnyUnderTheCourtyard(const std::string& material) {
    auto dir = test::scratchDir();
    const std::string scene = test::writeFile(
        dir / "bunny.kiln",
        "<kiln-scene>\n  " + material + "\n  <mesh file=\"" +
            test::shared("meshes/stanford-bunny.obj") +
            "\" material=\"m\"><matrix values=\"6.4 0 0 0.1 0 6.4 0 -0.2 0 0 6.4 0 0 0 0 "
            "1\"/></mesh>\n"
            "  <camera position=\"0 0.35 1.6\" look-at=\"0 0.3 0\" up=\"0 1 0\" fov=\"35\"/>\n"
            "</kiln-scene>\n");
    LoadOptions load;
    load.environmentMap = test::shared("envmaps/courtyard.exr");
    return loadScene(scene, load);
}

RenderJobOptions smallJob(int maxDepth = 5) {
    PathOptions path;
    path.maxDepth = maxDepth;
    path.microfacet = MicrofacetModel::GGX;
    RenderJobOptions o = test::jobOptions(48, 36, 4, path);
    o.settings.seed = 3;
    return o;
}

TEST(LightSamplePilot, ManySamplesWhereDirectLightIsTheNoiseFewWhereItIsNot) {
    Scene diffuse = bunnyUnderTheCourtyard(R"(<material name="m" albedo="0.6 0.6 0.6"/>)");
    Scene glossy = bunnyUnderTheCourtyard(
        R"(<material name="m" kind="microfacet" alpha="0.05" eta="0 0 0" k="1 1 1"/>)");
    auto diffuseAccel = makeEmbreeAccelerator(diffuse), glossyAccel = makeEmbreeAccelerator(glossy);
    RenderJob lit(diffuse, *diffuseAccel, smallJob()), shiny(glossy, *glossyAccel, smallJob());
    const LightSamplePilot& a = lit.lightSamplePilot();
    const LightSamplePilot& b = shiny.lightSamplePilot();
    // A diffuse surface under the map: light samples divide nearly all of its noise.
    EXPECT_GT(a.directVariance, 4 * a.otherVariance) << a.describe();
    EXPECT_GE(a.chosen, 4) << a.describe();
    // A narrow glossy lobe: a light sample rarely lands in it; the BSDF's sample carries the light.
    EXPECT_LT(b.directVariance, b.otherVariance) << b.describe();
    EXPECT_LE(b.chosen, 2) << b.describe();
    EXPECT_EQ(lit.options().path.lightSamples, a.chosen);
    EXPECT_EQ(shiny.options().path.lightSamples, b.chosen);
    // A light sample costs more than nothing and less than the rest of a camera sample's work.
    EXPECT_GT(a.lightCost, 0);
    EXPECT_LT(a.lightCost, a.baseCost);
}

TEST(LightSamplePilot, TheSameChoiceForAnyRegionThreadsAndSampleRange) {
    Scene s = bunnyUnderTheCourtyard(R"(<material name="m" albedo="0.6 0.6 0.6"/>)");
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions whole = smallJob(), part = whole;
    whole.settings.threads = 1;
    part.settings.threads = 3, part.settings.tileSize = 5;
    part.settings.regionX0 = 10, part.settings.regionX1 = 30;
    part.settings.regionY0 = 4, part.settings.regionY1 = 20;
    part.settings.sampleStart = 2, part.settings.spp = 9;
    RenderJob a(s, *accel, whole), b(s, *accel, part);
    EXPECT_EQ(a.lightSamplePilot().describe(), b.lightSamplePilot().describe());
    EXPECT_EQ(a.options().path.lightSamples, b.options().path.lightSamples);
}

TEST(LightSamplePilot, LeavesAGivenCountAndAreaLitScenesAlone) {
    Scene s = bunnyUnderTheCourtyard(R"(<material name="m" albedo="0.6 0.6 0.6"/>)");
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions given = smallJob();
    given.path.lightSamples = 3;
    RenderJob job(s, *accel, given);
    EXPECT_EQ(job.lightSamplePilot().chosen, 0);
    EXPECT_EQ(job.options().path.lightSamples, 3);

    Scene box = loadScene(test::cs184("sky/CBbunny.dae"));
    auto boxAccel = makeEmbreeAccelerator(box);
    RenderJob boxJob(box, *boxAccel, smallJob());
    EXPECT_EQ(boxJob.lightSamplePilot().chosen, 0);
    EXPECT_EQ(boxJob.options().path.lightSamples, 1);
}

TEST(LightSamplePilot, TheHeaderSaysWhatThePilotMeasured) {
    Scene s = bunnyUnderTheCourtyard(R"(<material name="m" albedo="0.6 0.6 0.6"/>)");
    auto accel = makeEmbreeAccelerator(s);
    RenderJob job(s, *accel, smallJob());
    Film film = job.makeFilm();
    RenderStats stats = job.render(film);
    Metadata meta = job.metadata(stats, film);
    auto value = [&](const std::string& key) {
        auto it = meta.find(key);
        return it == meta.end() ? std::string("(missing)") : it->second;
    };
    EXPECT_EQ(value("light_samples"), std::to_string(job.lightSamplePilot().chosen));
    EXPECT_NE(value("light_samples_pilot").find("relative variance"), std::string::npos)
        << value("light_samples_pilot");
}

}  // namespace
}  // namespace kiln
