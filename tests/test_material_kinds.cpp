// The material kind table (scene/material_kinds.h) and the BSDF registration (integrators/bsdf.h):
// every kind has one row, one BSDF class, and every reader takes every parameter the row names.
#include <fmt/format.h>

#include <set>

#include "integrators/bsdf.h"
#include "integrators/lights.h"
#include "scene/light_kinds.h"
#include "scene/material_kinds.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr MaterialKind kEveryKind[] = {MaterialKind::Lambertian, MaterialKind::Mirror,
                                       MaterialKind::Glass,      MaterialKind::Microfacet,
                                       MaterialKind::Refraction, MaterialKind::Glossy,
                                       MaterialKind::Emission,   MaterialKind::Principled};

TEST(MaterialKinds, EveryKindHasOneRowAndOneBsdfClass) {
    EXPECT_EQ(materialKinds().size(), std::size(kEveryKind));
    std::set<std::string> names;
    for (MaterialKind k : kEveryKind) {
        const MaterialKindSpec& spec = specOf(k);
        EXPECT_EQ(spec.kind, k);
        EXPECT_TRUE(names.insert(spec.name).second) << spec.name << " named twice";
        EXPECT_EQ(findMaterialKind(spec.name), &spec);
        EXPECT_STREQ(toString(k), spec.name);
        EXPECT_EQ(RegisteredBsdfs::handlerCount(k), 1) << spec.name;
    }
    EXPECT_EQ(findMaterialKind("velvet"), nullptr);
}

// What the row says of a kind agrees with what its BSDF does.
TEST(MaterialKinds, FactsAgreeWithTheBsdf) {
    for (MaterialKind k : kEveryKind) {
        Material m;
        m.kind = k;
        const MaterialKindSpec& spec = specOf(k);
        Bsdf bsdf(m);
        EXPECT_EQ(bsdf.isBlack(), spec.black) << spec.name;
        EXPECT_EQ(bsdf.isDiffuse(), spec.lambertian) << spec.name;
        EXPECT_EQ(bsdf.hasTransmission(), spec.transmission) << spec.name;
        if (spec.deltaSpecular) {
            EXPECT_TRUE(bsdf.isDelta()) << spec.name;
        }
    }
}

std::string valueIn(ParamRange range) { return range == ParamRange::AtLeastOne ? "1.5" : "0.5"; }
std::string valueOutside(ParamRange range) {
    return range == ParamRange::AtLeastOne ? "0.5" : "-1";
}

// A .kiln scene in its own folder of the test's scratch directory: a triangle of material m.
std::filesystem::path writeKilnScene(const std::string& name, const std::string& material) {
    static std::filesystem::path scratch;
    static const ::testing::TestInfo* owner = nullptr;
    const auto* current = ::testing::UnitTest::GetInstance()->current_test_info();
    if (owner != current) scratch = test::scratchDir(), owner = current;
    auto dir = scratch / name;
    std::filesystem::create_directories(dir);
    test::writeFile(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    test::writeFile(dir / "scene.kiln",
                    "<kiln-scene>" + material +
                        "<mesh file=\"quad.obj\" material=\"m\"/>"
                        "<light kind=\"point\" position=\"0 0 3\" radiance=\"1 1 1\"/>"
                        "</kiln-scene>\n");
    return dir / "scene.kiln";
}

// Every parameter of every .kiln kind is read, lands in its field, and kiln info prints it.
TEST(MaterialKinds, KilnReaderTakesEveryParameterOfTheRow) {
    for (const MaterialKindSpec& spec : materialKinds()) {
        if (!spec.inKiln) continue;
        std::string attrs;
        for (const MaterialParam& p : spec.params)
            attrs +=
                fmt::format(" {}=\"{}\"", p.name, p.colour ? "0.25 0.5 0.75" : valueIn(p.range));
        auto path =
            writeKilnScene(std::string("kind_") + spec.name,
                           fmt::format("<material name=\"m\" kind=\"{}\"{}/>", spec.name, attrs));
        Scene s = loadScene(path.string());
        const Material* m = test::findMaterial(s, spec.kind);
        ASSERT_TRUE(m) << spec.name;
        for (const MaterialParam& p : spec.params) {
            if (p.colour) {
                EXPECT_EQ(m->*p.colour, Color(0.25f, 0.5f, 0.75f)) << spec.name << " " << p.name;
            } else {
                EXPECT_FLOAT_EQ(m->*p.scalar, std::stof(valueIn(p.range)))
                    << spec.name << " " << p.name;
            }
            EXPECT_NE(describeParams(*m).find(p.name), std::string::npos) << spec.name;
        }
        EXPECT_NE(sceneInfoText(s).find(describeParams(*m)), std::string::npos) << spec.name;
    }
}

// A value outside a parameter's range is refused with the row's rule, naming the parameter.
TEST(MaterialKinds, KilnReaderRefusesValuesOutsideTheRange) {
    for (const MaterialKindSpec& spec : materialKinds()) {
        if (!spec.inKiln) continue;
        for (const MaterialParam& p : spec.params) {
            if (p.colour || p.range == ParamRange::Any) continue;
            std::string attrs;
            for (const MaterialParam& q : spec.params)
                attrs += fmt::format(" {}=\"{}\"", q.name,
                                     q.colour   ? "0.5 0.5 0.5"
                                     : &q == &p ? valueOutside(q.range)
                                                : valueIn(q.range));
            auto path = writeKilnScene(
                fmt::format("range_{}_{}", spec.name, p.name),
                fmt::format("<material name=\"m\" kind=\"{}\"{}/>", spec.name, attrs));
            test::expectError(path.string(),
                              fmt::format("{} must be {}", p.name, rangeText(p.range)));
        }
    }
}

// A required parameter left out is an error; an optional one keeps the kind's default.
TEST(MaterialKinds, RequiredParametersAreRequired) {
    test::expectError(
        writeKilnScene("foreign", "<material name=\"m\" kind=\"mirror\" ior=\"1.5\"/>").string(),
        "unknown attribute 'ior' for kind mirror");
    auto path = writeKilnScene("required",
                               "<material name=\"m\" kind=\"microfacet\" alpha=\"0.3\" "
                               "eta=\"1 1 1\"/>");
    test::expectError(path.string(), "k needs 3 numbers");
    path = writeKilnScene("optional", "<material name=\"m\" kind=\"principled\"/>");
    Scene s = loadScene(path.string());
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    EXPECT_FLOAT_EQ(m->roughness, 0.5f);  // the kind's default, not Material{}'s
    EXPECT_EQ(m->albedo, Color(0.8f));
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// The light kind table: one row and one emitter class per kind, with facts that hold together.
TEST(LightKinds, EveryKindHasOneRow) {
    constexpr LightKind kEvery[] = {
        LightKind::Area,        LightKind::MeshEmitter, LightKind::Point,      LightKind::Spot,
        LightKind::Directional, LightKind::Ambient,     LightKind::Environment};
    EXPECT_EQ(lightKinds().size(), std::size(kEvery));
    std::set<std::string> names;
    for (LightKind k : kEvery) {
        EXPECT_EQ(specOf(k).kind, k);
        EXPECT_TRUE(names.insert(toString(k)).second) << toString(k);
        EXPECT_EQ(RegisteredEmitters::handlerCount(k), 1) << toString(k);
        EXPECT_FALSE(specOf(k).delta && (specOf(k).infinite || specOf(k).surface)) << toString(k);
        Light l;
        l.kind = k;
        // A delta light can never be hit; a light at infinity always can.
        if (specOf(k).delta) {
            EXPECT_FALSE(specOf(k).hittable(l));
        }
        if (specOf(k).infinite) {
            EXPECT_TRUE(specOf(k).hittable(l));
        }
    }
    Light area;
    area.kind = LightKind::Area;
    EXPECT_FALSE(specOf(LightKind::Area).hittable(area));  // a rectangle no mesh draws
    area.hasMesh = true;
    EXPECT_TRUE(specOf(LightKind::Area).hittable(area));
}

}  // namespace
}  // namespace kiln
