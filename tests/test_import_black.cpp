// Files that rendered all black in the Assimp corpus (docs/robustness.md): each is either read
// right now or loaded with a warning that says why its image is black.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "kiln_run.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

std::string corpus(const std::string& rel) {
    std::string path = "/usr/share/assimp/models/" + rel;
    EXPECT_TRUE(std::filesystem::exists(path)) << "assimp-testmodels (tools/setup.sh) missing";
    return path;
}

// An OBJ quad whose material states Kd 0 0 0: black as written, and said so.
TEST(ImportBlack, BlackMaterialsAreNamedInAWarning) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "black.mtl", "newmtl black\nKd 0 0 0\n");
    Scene s = loadScene(test::writeFile(
        dir / "black.obj",
        "mtllib black.mtl\nusemtl black\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
    EXPECT_TRUE(test::hasWarning(s, "diffuse colour is black"));
    test::writeFile(dir / "grey.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
    Scene grey = loadScene(test::writeFile(
        dir / "grey.obj",
        "mtllib grey.mtl\nusemtl grey\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
    EXPECT_FALSE(test::hasWarning(grey, "diffuse colour is black"));
}

// The black-image warning comes from what the camera sees (kiln render probes the frame), so it
// cannot be dodged: a point light of intensity 1 at 1000 units from a unit quad gives it 1e-6; a
// light inside the scene's bounds that grazes the quad (it dodged the old bound on light power,
// as Collada/cube_tristrips.dae's light inside its cube did) gives it nothing. The same light 2
// units away lights it, and says nothing.
TEST(ImportBlack, WhatTheCameraSeesDecidesTheBlackImageWarning) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    auto render = [&](const std::string& lights) {
        std::string scene = test::writeFile(
            dir / "s.kiln", R"(<?xml version="1.0"?><kiln-scene><mesh file="quad.obj"/>)" + lights +
                                "</kiln-scene>");
        test::CliRun r =
            test::runKiln("render " + scene + " -r 32 24 -s 1 --json --progress none -o " +
                          (dir / "out").string());
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(r.out)["warnings"].dump();
    };
    auto point = [](const char* position) {
        return std::string(R"(<light kind="point" radiance="1 1 1" position=")") + position +
               R"("/>)";
    };
    std::string far = render(point("0.5 0.5 1000"));
    EXPECT_NE(far.find("the image will look black"), std::string::npos) << far;
    EXPECT_NE(far.find("mean luminance of"), std::string::npos) << far;
    std::string grazing = render(point("0.5 0.5 1000") + point("0.5 0.5 0"));
    EXPECT_NE(grazing.find("the image will look black"), std::string::npos) << grazing;
    std::string near = render(point("0.5 0.5 2"));
    EXPECT_EQ(near.find("look black"), std::string::npos) << near;
}

// AC's SphereWithLight has no camera and its light behind the sphere as the default front view
// sees it: the default framing looks from the light's side.
TEST(ImportBlack, DefaultFramingLooksFromTheLightsSide) {
    Scene s = loadScene(corpus("AC/SphereWithLight.ac"));
    ASSERT_FALSE(s.hasFileCamera);
    const Light* light = test::findLight(s, LightKind::Point);
    ASSERT_NE(light, nullptr);
    Vec3 centre = s.storedBounds().centroid();
    EXPECT_GT(dot(s.camera.position - centre, light->position - centre), 0.0f);
}

// Assimp 5.2 reports a SIB light's target point as its direction: heffalump's sun shone upwards.
TEST(ImportBlack, SibLightsPointAtTheirTargets) {
    Scene s = loadScene(corpus("SIB/heffalump.sib"));
    const Light* sun = test::findLight(s, LightKind::Directional);
    ASSERT_NE(sun, nullptr);
    EXPECT_LT(sun->direction.y, -0.5f);  // from (-1.34, 5.60, 0) towards (0, 3.60, 0)
}

// FBX states its lamp's falloff (linear: Assimp's factor 0.000667); as 1 / d^2 the lamp gave the
// model 2.7e-6 at 600 units. Lights that state none keep exactly 1 / d^2.
TEST(ImportBlack, FbxLightsFallOffAsTheFileStates) {
    Scene s = loadScene(corpus("FBX/huesitos.fbx"));
    const Light* lamp = test::findLight(s, LightKind::Point);
    ASSERT_NE(lamp, nullptr);
    EXPECT_TRUE(lamp->attenuationStated);
    EXPECT_NEAR(lamp->attenuationLinear, 0.000666667f, 1e-8f);
    EXPECT_NEAR(lamp->falloffDenominator(600.0f * 600.0f), 0.4f, 1e-5f);
    EXPECT_FALSE(test::hasWarning(s, "irradiance of at most"));
    Light physical;
    EXPECT_EQ(physical.falloffDenominator(2.5f), 2.5f);
}

// MDL without skins: Assimp's colour (0, 0, 0, 0) is not the file's; Quick3D: Assimp's camera at
// the origin and black light are not the file's; AMF: constellations and extra volumes are lost.
TEST(ImportBlack, AssimpReaderLimitsAreWarnings) {
    Scene mdl = loadScene(corpus("MDL/MDL5 (3DGS A5)/PhosphoricAcid_MDl5.mdl"));
    EXPECT_EQ(mdl.materials[0].albedo, Material{}.albedo);
    EXPECT_TRUE(test::hasWarning(mdl, "has no skin"));
    Scene q3d = loadScene(corpus("Q3D/WusonOrange.q3s"));
    EXPECT_FALSE(q3d.hasFileCamera);
    EXPECT_TRUE(test::hasWarning(q3d, "Quick3D"));
    EXPECT_NE(test::findLight(q3d, LightKind::Directional), nullptr);  // the default rig
    Scene amf = loadScene(corpus("AMF/test8.amf"));
    EXPECT_TRUE(test::hasWarning(amf, "constellation"));
    EXPECT_TRUE(test::hasWarning(amf, "first <volume>"));
    Scene zeros = loadScene(corpus("AMF/test1.amf"));  // no colours in the file: Assimp's zeros
    EXPECT_TRUE(zeros.meshes[0].colors.empty());
    EXPECT_TRUE(test::hasWarning(zeros, "(0, 0, 0, 0)"));
    Scene blend = loadScene(corpus("BLEND/BlenderDefault_250.blend"));  // Assimp: (-1, -1, -1, -1)
    EXPECT_TRUE(blend.meshes[0].colors.empty());
}

// OpenGEX's parser prints "nullptr returned by creating DDLNode." to std::cerr: kiln's error must
// stay the only line.
TEST(ImportBlack, AssimpPrintsNothingBesideKilnsError) {
    std::ostringstream printed;
    std::streambuf* old = std::cerr.rdbuf(printed.rdbuf());
    EXPECT_THROW(loadScene(corpus("OpenGEX/empty_camera.ogex")), SceneError);
    std::cerr.rdbuf(old);
    EXPECT_EQ(printed.str(), "");
}

// The beauty's mean luminance of a small render (the file's own camera and lights).
double beautyMean(const Scene& s, int w = 32, int h = 24, int spp = 4) {
    auto accel = makeEmbreeAccelerator(s);
    Film f = test::renderJob(s, *accel, test::jobOptions(w, h, spp));
    double sum = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) sum += luminance(f.pixel(x, y));
    return sum / (w * h);
}

// kiln's direct light against the authoring tool's shading formula, pixel by pixel: `shown`
// gives what the tool shows at a surface point (world position, normal, albedo). Over pixels
// wholly on one surface, lit in both: the median ratio kiln / tool and the fraction within 5 %
// (a pixel's normal and position are means over its samples, so curved surfaces differ a little).
struct FormulaMatch {
    double median = 0, within = 0;
    int pixels = 0;
};
FormulaMatch againstFormula(const Scene& s, const std::function<double(Vec3d, Vec3, Color)>& shown,
                            int w = 128, int h = 96) {
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = test::jobOptions(w, h, 4, {}, AovRequest::parse("direct,albedo,N,P", 5));
    Film f = test::renderJob(s, *accel, o);
    size_t dr = test::aovChannel(f, "direct.R"), ar = test::aovChannel(f, "albedo.R"),
           nx = test::aovChannel(f, "N.X"), px = test::aovChannel(f, "P.X");
    std::vector<double> ratios;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Vec3 n(f.aov(x, y, nx), f.aov(x, y, nx + 1), f.aov(x, y, nx + 2));
            // A pixel wholly on the surface, whose samples' normals (smooth shading) agree.
            if (f.alpha(x, y) < 1 || length(n) < 0.98f) continue;
            n = normalize(n);
            Vec3d p(f.aov(x, y, px), f.aov(x, y, px + 1), f.aov(x, y, px + 2));
            Color albedo(f.aov(x, y, ar), f.aov(x, y, ar + 1), f.aov(x, y, ar + 2));
            Color direct(f.aov(x, y, dr), f.aov(x, y, dr + 1), f.aov(x, y, dr + 2));
            double tool = shown(p, n, albedo), kiln = luminance(direct);
            if (tool > 1e-4 && kiln > 1e-4) ratios.push_back(kiln / tool);  // lit, not shadowed
        }
    FormulaMatch m;
    m.pixels = int(ratios.size());
    if (ratios.empty()) return m;
    std::sort(ratios.begin(), ratios.end());
    m.median = ratios[ratios.size() / 2];
    for (double r : ratios) m.within += std::abs(r - 1) <= 0.05;
    m.within /= double(ratios.size());
    return m;
}

// Blender Internal's lamp: albedo * energy * visibility(d) * N.L, no 1 / pi
// (render/intern/source/shadeoutput.c, lamp_get_visibility), for the lamp of `file`.
std::function<double(Vec3d, Vec3, Color)> blenderInternal(const Scene& s, float energy,
                                                          std::function<double(double)> falloff) {
    const Light* lamp = test::findLight(s, LightKind::Point);
    EXPECT_NE(lamp, nullptr);
    Vec3d at = lamp ? s.world(lamp->position) : Vec3d(0.0);
    return [=](Vec3d p, Vec3 n, Color albedo) {
        Vec3d toLamp = at - p;
        double d = length(toLamp), cosine = dot(Vec3d(n), toLamp) / d;
        return luminance(albedo) * energy * falloff(d) * std::max(0.0, cosine);
    };
}

// Issue #33 item 1: Blender lamps as Blender shows them, from the file's own lamp data (Assimp
// passes energy * colour and no Distance or falloff). Blender Internal (files before 2.80) lights
// a surface by colour * energy * falloff * N.L, without kiln's 1 / pi: intensity pi * energy and
// its falloff with Distance D = 30: inverse square D / (D + d^2) (2.5x-2.7x defaults), inverse
// linear D / (D + d) (2.4x); an area lamp 2 pi energy D^2 / area. Blender 2.80+ states watts: a
// 1000 W point light is 1000 / (4 pi) W/sr with 1 / d^2. Files that rendered near-black (beauty
// mean 9e-7 to 1.8e-3) are lit, pixel for pixel as Blender Internal's formula says.
TEST(LightConventions, BlenderLampsAsBlenderShowsThem) {
    auto point = [](const Scene& s) {
        const Light* l = test::findLight(s, LightKind::Point);
        EXPECT_NE(l, nullptr);
        return l ? *l : Light{};
    };
    for (const char* file :
         {"BLEND/BlenderDefault_250.blend", "BLEND/BlenderDefault_250_Compressed.blend"}) {
        Light l = point(loadScene(corpus(file)));
        EXPECT_NEAR(l.radiance.x, kPi, 1e-5f) << file;
        EXPECT_TRUE(l.attenuationStated) << file;
        EXPECT_EQ(l.attenuationConstant, 1.0f) << file;
        EXPECT_EQ(l.attenuationLinear, 0.0f) << file;
        EXPECT_NEAR(l.attenuationQuadratic, 1.0f / 30, 1e-7f) << file;
    }
    for (const char* file : {"BLEND/Suzanne_248.blend", "BLEND/yxa_1.blend"}) {  // yxa: big-endian
        Light l = point(loadScene(corpus(file)));
        EXPECT_NEAR(l.radiance.x, kPi, 1e-5f) << file;
        EXPECT_NEAR(l.attenuationLinear, 1.0f / 30, 1e-7f) << file;
        EXPECT_EQ(l.attenuationQuadratic, 0.0f) << file;
    }
    Light watts = point(loadScene(corpus("BLEND/box.blend")));
    EXPECT_NEAR(watts.radiance.x, 1000.0f / (4 * kPi), 1e-3f);
    EXPECT_FALSE(watts.attenuationStated);
    Scene area = loadScene(corpus("BLEND/AreaLight_269.blend"));
    bool foo = false;
    for (const Light& l : area.lights)
        if (l.name == "Foo") {  // energy 1, square 1 x 1, Distance 25
            foo = true;
            EXPECT_EQ(l.kind, LightKind::Area);
            EXPECT_NEAR(l.radiance.x, 2 * kPi * 625, 0.1f);
        }
    EXPECT_TRUE(foo);
    auto invSquare = [](double d) { return 30 / (30 + d * d); };
    auto invLinear = [](double d) { return 30 / (30 + d); };
    const std::pair<const char*, std::function<double(double)>> lit[] = {
        {"BLEND/BlenderDefault_250.blend", invSquare},
        {"BLEND/SuzanneSubdiv_252.blend", invSquare},
        {"BLEND/Suzanne_248.blend", invLinear},
        {"BLEND/TexturedCube_ImageGlob_248.blend", invLinear},
        {"BLEND/HUMAN.blend", invLinear}};
    for (const auto& [file, falloff] : lit) {
        Scene s = loadScene(corpus(file));
        EXPECT_GT(beautyMean(s), 1e-3) << file;  // no longer under the black-image line
        FormulaMatch m = againstFormula(s, blenderInternal(s, 1.0f, falloff));
        std::printf(
            "%s: kiln / Blender Internal over %d lit pixels: median %.4f, %.0f %% within "
            "5 %%\n",
            file, m.pixels, m.median, 100 * m.within);
        EXPECT_GT(m.pixels, 20) << file;
        EXPECT_NEAR(m.median, 1.0, 0.015) << file;
        EXPECT_GT(m.within, 0.8) << file;
    }
}

// Issue #33 item 2: COLLADA's common profile lights a <lambert> surface by diffuse * colour *
// attenuation * N.L, attenuation 1 / (c + l d + q d^2), defaults 1, 0, 0 (no falloff): intensity
// pi * colour and the file's falloff, through kiln's XML pass (.dae) and Assimp (.xml) alike. The
// Maya cubes with a light of colour 1 twelve units away (beauty mean 1.8e-8 to 1.8e-5) are lit as
// the formula says. The CS184 library keeps the course's rule (colour as intensity, 1 / d^2): its
// images do not change. ASE/anim2.ASE: its two directional lights graze every face the camera
// sees; what lit them in 3ds Max is its Skylight, which Assimp reports as a point light 120 units
// away: kiln reads the file's light type and lights it as a sky.
TEST(LightConventions, ColladaAndAseAsTheirToolsShowThem) {
    Scene cube = loadScene(corpus("Collada/cube_triangulate.dae"));
    const Light* l = test::findLight(cube, LightKind::Point);
    ASSERT_NE(l, nullptr);
    EXPECT_NEAR(l->radiance.x, kPi, 1e-5f);
    EXPECT_TRUE(l->attenuationStated);
    EXPECT_EQ(l->falloffDenominator(144.0f), 1.0f);
    for (const char* file :
         {"Collada/cube_triangulate.dae", "Collada/cube_tristrips.dae",
          "Collada/cube_xmlspecialchars.dae", "Collada/cube_UTF8BOM.dae", "Collada/AsXML.xml"}) {
        Scene s = loadScene(corpus(file));
        EXPECT_GT(beautyMean(s), 1e-3) << file;
        // Every light of colour 1, no falloff: the surface shows diffuse * sum of N.L.
        std::vector<Vec3d> lights;
        for (const Light& light : s.lights) lights.push_back(s.world(light.position));
        FormulaMatch m = againstFormula(s, [&](Vec3d p, Vec3 n, Color albedo) {
            double sum = 0;
            for (const Vec3d& at : lights) sum += std::max(0.0, dot(Vec3d(n), normalize(at - p)));
            return luminance(albedo) * sum;
        });
        std::printf(
            "%s: kiln / COLLADA common profile over %d lit pixels: median %.4f, %.0f %% "
            "within 5 %%\n",
            file, m.pixels, m.median, 100 * m.within);
        EXPECT_GT(m.pixels, 20) << file;
        EXPECT_NEAR(m.median, 1.0, 0.01) << file;
    }
    const Light* course =
        test::findLight(loadScene(test::cs184("meshedit/cow.dae")), LightKind::Directional);
    ASSERT_NE(course, nullptr);
    EXPECT_EQ(course->radiance.x, 1.0f);
    Scene spheres = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    for (const Light& light : spheres.lights) EXPECT_FALSE(light.attenuationStated);

    Scene ase = loadScene(corpus("ASE/anim2.ASE"));
    const Light* sky = test::findLight(ase, LightKind::Ambient);
    ASSERT_NE(sky, nullptr);
    EXPECT_EQ(sky->name, "Sky01");
    EXPECT_NEAR(sky->radiance.x, 0.95f, 1e-6f);
    EXPECT_TRUE(test::hasWarning(ase, "3ds Max Skylight"));
    const Light* sun = test::findLight(ase, LightKind::Directional);
    ASSERT_NE(sun, nullptr);
    EXPECT_NEAR(sun->radiance.x, kPi, 1e-5f);
    EXPECT_GT(beautyMean(ase), 1e-3);
}

}  // namespace
}  // namespace kiln
