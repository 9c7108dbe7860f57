// Every scene of the CS184 library imports with the counts of its SOURCES.md and the CGL extras it
// holds.
#include <fstream>
#include <nlohmann/json.hpp>

#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

using test::cs184;

struct Expected {
    const char* path;
    uint64_t triangles;  // as SOURCES.md lists them (rendered; CBspheres_refract: 10 placed)
    uint64_t spheres;
    std::map<std::string, int> lights;
};

void PrintTo(const Expected& e, std::ostream* os) { *os << e.path; }

class Cs184Import : public ::testing::TestWithParam<Expected> {};

TEST_P(Cs184Import, CountsAndLightKinds) {
    const Expected& e = GetParam();
    Scene s = loadScene(cs184(e.path));
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.triangles, e.triangles);
    EXPECT_EQ(sum.spheres, e.spheres);
    EXPECT_EQ(sum.lights, e.lights);
    EXPECT_TRUE(s.hasFileCamera);
    EXPECT_TRUE(s.framedByCourseRule);
}

// The CGL area light and the emissive ceiling quad are one light (mergeAreaLightsWithEmitters).
const std::map<std::string, int> kCornellLights{{"area", 1}};
INSTANTIATE_TEST_SUITE_P(
    Library, Cs184Import,
    ::testing::Values(
        Expected{"keenan/banana.dae", 2458, 0, {{"ambient", 1}, {"directional", 1}}},
        Expected{"keenan/building.dae", 39506, 0, {{"ambient", 1}, {"directional", 1}}},
        Expected{"meshedit/beetle.dae", 7558, 0, {{"directional", 1}}},
        Expected{"meshedit/cow.dae", 5856, 0, {{"directional", 1}}},
        Expected{"meshedit/maxplanck.dae", 50801, 0, {{"directional", 1}}},
        Expected{"meshedit/peter.dae", 40018, 0, {{"directional", 1}}},
        Expected{"meshedit/teapot.dae", 2464, 0, {{"directional", 1}}},
        Expected{"simple/cube.dae", 12, 0, {{"point", 1}}},
        Expected{"simple/plane.dae", 2, 0, {{"point", 1}}},
        Expected{"sky/CBbunny.dae", 28588, 0, kCornellLights},
        Expected{"sky/CBbunny_microfacet_cu.dae", 28588, 0, kCornellLights},
        Expected{"sky/CBcoil.dae", 7884, 0, kCornellLights},
        Expected{"sky/CBempty.dae", 12, 0, {{"point", 1}, {"emissive_mesh", 1}}},
        Expected{"sky/CBgems.dae", 252, 0, kCornellLights},
        Expected{"sky/CBspheres.dae", 12, 2, kCornellLights},
        Expected{"sky/CBspheres_lambertian.dae", 12, 2, kCornellLights},
        Expected{"sky/CBspheres_microfacet_al_ag.dae", 12, 2, kCornellLights},
        Expected{"sky/CBspheres_tex.dae", 12, 2, kCornellLights},
        Expected{"sky/bunny.dae", 33696, 0, {{"ambient", 1}}},
        Expected{"sky/bunny_microfacet_cu.dae", 33696, 0, {{"ambient", 1}}},
        Expected{"sky/bunny_microfacet_cu_unlit.dae", 33696, 0, {{"ambient", 1}}},
        Expected{"sky/bunny_unlit.dae", 33696, 0, {{"ambient", 1}}},
        Expected{
            "variants/2018-2020/sky/CBempty_dark.dae", 12, 0, {{"point", 1}, {"emissive_mesh", 1}}},
        Expected{"variants/2018-2020/sky/CBempty_light.dae",
                 12,
                 0,
                 {{"point", 1}, {"emissive_mesh", 1}}},
        Expected{"variants/2018-2020/sky/CBspheres_glossy.dae", 12, 2, kCornellLights},
        Expected{"variants/2018-2020/sky/bunny.dae", 33696, 0, {{"ambient", 1}}},
        // The p3-2 template comments out the emitter quad: 10 of its 12 triangles are placed.
        Expected{"variants/p3-2-sp23/sky/CBspheres_refract.dae", 10, 2, {{"area", 1}}}),
    [](const auto& info) {
        std::string n = info.param.path;
        for (char& c : n)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return n;
    });

TEST(Cs184Extras, CBspheresGlassMirrorAndAreaLight) {
    Scene s = loadScene(cs184("sky/CBspheres.dae"));
    const Material* glass = test::findMaterial(s, MaterialKind::Glass);
    ASSERT_NE(glass, nullptr);
    EXPECT_FLOAT_EQ(glass->ior, 1.45f);
    EXPECT_EQ(glass->transmittance, Color(1.0f));
    EXPECT_EQ(glass->reflectance, Color(1.0f));
    EXPECT_FLOAT_EQ(glass->roughness, 0.0f);
    const Material* mirror = test::findMaterial(s, MaterialKind::Mirror);
    ASSERT_NE(mirror, nullptr);
    EXPECT_EQ(mirror->reflectance, Color(1.0f));
    // Spheres: radius .3 placed by their node matrices, then the Z-up fix (x -> -x, y <-> z).
    ASSERT_EQ(s.spheres.size(), 2u);
    EXPECT_FLOAT_EQ(s.spheres[0].radius, 0.3f);
    EXPECT_NEAR(s.spheres[0].center.x, 0.4f, 1e-6f);
    EXPECT_NEAR(s.spheres[0].center.y, 0.3f, 1e-6f);
    EXPECT_NEAR(s.spheres[0].center.z, 0.3f, 1e-6f);
    EXPECT_EQ(s.materials[s.spheres[0].material].kind, MaterialKind::Glass);
    EXPECT_EQ(s.materials[s.spheres[1].material].kind, MaterialKind::Mirror);

    const Light* area = test::findLight(s, LightKind::Area);
    ASSERT_NE(area, nullptr);
    EXPECT_EQ(area->radiance, Color(10.0f));
    EXPECT_NEAR(area->position.y, 1.49f, 1e-6f);
    EXPECT_NEAR(area->direction.y, -1.0f, 1e-6f);  // facing down
    EXPECT_NEAR(length(area->dimX), 0.6f, 1e-6f);
    EXPECT_NEAR(length(area->dimY), 0.8f, 1e-6f);
    const Material* emitter = test::findMaterial(s, MaterialKind::Emission);
    ASSERT_NE(emitter, nullptr);
    EXPECT_EQ(emitter->emission, Color(10.0f));
    // The area light is bound to the emissive quad that occupies its rectangle.
    ASSERT_TRUE(area->hasMesh);
    EXPECT_EQ(s.materials[s.meshes[area->mesh].materialOf(0)].kind, MaterialKind::Emission);
}

TEST(Cs184Extras, MicrofacetParametersAsInTheFile) {
    Scene s = loadScene(cs184("sky/CBspheres_microfacet_al_ag.dae"));
    ASSERT_EQ(s.spheres.size(), 2u);
    std::vector<const Material*> metals;
    for (const Sphere& sp : s.spheres) metals.push_back(&s.materials[sp.material]);
    // Which sphere holds which metal is the file's binding; check both sets are present exactly.
    auto isAl = [](const Material* m) {
        return m->kind == MaterialKind::Microfacet && m->alpha == 0.25f &&
               m->eta == Color(0.059193f, 0.059881f, 0.047366f) &&
               m->k == Color(4.1283f, 3.5892f, 2.8132f);
    };
    auto isAg = [](const Material* m) {
        return m->kind == MaterialKind::Microfacet && m->alpha == 0.025f &&
               m->eta == Color(1.3352f, 1.0109f, 0.68955f) &&
               m->k == Color(7.3398f, 6.6157f, 5.6471f);
    };
    EXPECT_TRUE((isAl(metals[0]) && isAg(metals[1])) || (isAg(metals[0]) && isAl(metals[1])));

    Scene cu = loadScene(cs184("sky/CBbunny_microfacet_cu.dae"));
    const Material* m = test::findMaterial(cu, MaterialKind::Microfacet);
    ASSERT_NE(m, nullptr);
    EXPECT_FLOAT_EQ(m->alpha, 0.05f);
    EXPECT_EQ(m->eta, Color(0.33228f, 1.0162f, 1.2474f));
    EXPECT_EQ(m->k, Color(3.1646f, 2.5785f, 2.4603f));
}

TEST(Cs184Extras, GlossyRefractionAndDefaultLambertian) {
    Scene glossy = loadScene(cs184("variants/2018-2020/sky/CBspheres_glossy.dae"));
    const Material* g = test::findMaterial(glossy, MaterialKind::Glossy);
    ASSERT_NE(g, nullptr);
    EXPECT_FLOAT_EQ(g->shininess, 50.0f);
    EXPECT_EQ(g->reflectance, Color(1.0f));
    Scene refract = loadScene(cs184("variants/p3-2-sp23/sky/CBspheres_refract.dae"));
    const Material* r = test::findMaterial(refract, MaterialKind::Refraction);
    ASSERT_NE(r, nullptr);
    EXPECT_FLOAT_EQ(r->ior, 1.45f);
    // No CGL child: Lambertian with the Phong diffuse colour (CBbunny's red left wall).
    Scene bunny = loadScene(cs184("sky/CBbunny.dae"));
    bool foundRed = false;
    for (const Material& m : bunny.materials)
        if (m.name == "leftWall") {
            foundRed = true;
            EXPECT_EQ(m.kind, MaterialKind::Lambertian);
            EXPECT_EQ(m.albedo, Color(0.6f, 0.2f, 0.2f));
        }
    EXPECT_TRUE(foundRed);
}

TEST(Cs184Extras, CBgemsLoadsDespiteItsShortCameraMatrix) {
    Scene s = loadScene(cs184("sky/CBgems.dae"));
    EXPECT_EQ(s.uniqueTriangles(), 252u);
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_NE(s.warnings[0].find("15 numbers"), std::string::npos);
    EXPECT_EQ(test::countKind(s, MaterialKind::Glass), 3);
    // The course reads the 15 numbers with the 16th as 0: the camera looks down -z from +z.
    EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-5f);
}

TEST(Cs184Extras, CornellBoxSpansTheCourseBounds) {
    Scene s = loadScene(cs184("sky/CBempty.dae"));
    Bounds3 b = s.storedBounds();
    EXPECT_NEAR(b.lo.x, -1, 1e-5);
    EXPECT_NEAR(b.hi.x, 1, 1e-5);
    EXPECT_NEAR(b.lo.y, 0, 1e-5);
    EXPECT_NEAR(b.hi.y, 1.5, 1e-5);
    EXPECT_NEAR(b.lo.z, -1, 1e-5);
    EXPECT_NEAR(b.hi.z, 1, 1e-5);
    // CBempty's only light is the point light of technique_common (colour 5).
    const Light* point = test::findLight(s, LightKind::Point);
    ASSERT_NE(point, nullptr);
    EXPECT_EQ(point->radiance, Color(5.0f));
}

TEST(Cs184Extras, InfoJsonHasTheDocumentedKeys) {
    Scene s = loadScene(cs184("sky/CBspheres.dae"));
    auto json = nlohmann::json::parse(sceneInfoJson(s));
    EXPECT_EQ(json["triangles"], 12);
    EXPECT_EQ(json["spheres"], 2);
    EXPECT_EQ(json["materials"]["glass"], 1);
    EXPECT_EQ(json["lights"], nlohmann::json({{"area", 1}}));
    for (const char* key : {"meshes", "camera", "bbox", "load_seconds"})
        EXPECT_TRUE(json.contains(key)) << key << "\n" << json;
}

// A standard COLLADA <emission><color> (no CGL extra) is a light too, as the CGL rules make every
// emitting material; it used to become a black Lambertian surface and the default rig.
TEST(Cs184Extras, StandardColladaEmissionIsALight) {
    std::ifstream in(test::repo("scenes/cornell.dae"));
    std::string dae((std::istreambuf_iterator<char>(in)), {});
    const std::string cgl =
        "<lambert><diffuse><color>0.78 0.78 0.78 1</color></diffuse></lambert></technique>"
        "</profile_COMMON><extra><technique profile=\"CGL\"><emission><radiance>8 8 8</radiance>"
        "</emission></technique></extra>";
    const std::string standard =
        "<lambert><emission><color>8 8 8 1</color></emission><diffuse><color>0.78 0.78 0.78 "
        "1</color></diffuse></lambert></technique></profile_COMMON>";
    size_t at = dae.find(cgl);
    ASSERT_NE(at, std::string::npos);
    dae.replace(at, cgl.size(), standard);
    Scene s = loadScene(test::writeFile(test::scratchDir() / "standard_emission.dae", dae));
    Scene original = loadScene(test::repo("scenes/cornell.dae"));
    ASSERT_EQ(s.materials.size(), original.materials.size());
    for (size_t i = 0; i < s.materials.size(); ++i) {
        EXPECT_EQ(s.materials[i].kind, original.materials[i].kind) << s.materials[i].name;
        EXPECT_EQ(s.materials[i].emission, original.materials[i].emission) << s.materials[i].name;
    }
    EXPECT_EQ(s.lights.size(), original.lights.size());
}

}  // namespace
}  // namespace kiln
