// A principled material's metallic-roughness, emissive and occlusion textures and the glTF sampler
// wrap modes (scenes/assets, written by tools/make_asset_scenes.py): each texture changes shading
// as the constant material it stands for would, and what kiln does not read is named once.
#include <fstream>
#include <nlohmann/json.hpp>

#include "color/image_input.h"
#include "color/texture.h"
#include "renderer/accel/accelerator.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr int kSize = 64;  // the asset scenes' camera sees x, y in [-1, 1]: 32 pixels a unit

std::string assetScene(const std::string& name) { return test::repo("scenes/assets/" + name); }

Film render(const Scene& s, int spp, const PathOptions& path = {}, const AovRequest& aovs = {}) {
    auto accel = makeEmbreeAccelerator(s);
    return test::renderJob(s, *accel, test::jobOptions(kSize, kSize, spp, path, aovs));
}

// Paired differences of two renders over pixel columns [x0, x1): their mean, its standard error
// (from their spread) and the first render's mean luminance there.
struct Paired {
    double mean = 0, se = 0, level = 0;
};
Paired paired(const Film& a, const Film& b, int x0, int x1) {
    double sum = 0, sum2 = 0, level = 0;
    int n = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = x0; x < x1; ++x) {
            double d = luminance(a.pixel(x, y)) - luminance(b.pixel(x, y));
            sum += d, sum2 += d * d, level += luminance(a.pixel(x, y)), ++n;
        }
    Paired p;
    p.mean = sum / n;
    p.se = std::sqrt(std::max(0.0, sum2 / n - p.mean * p.mean) / n);
    p.level = level / n;
    return p;
}

// One texture for both, glTF's channels: B metallic, G roughness.
void expectGltfMetallicRoughness(const Material& m) {
    ASSERT_GE(m.maps.metallicTexture, 0);
    EXPECT_EQ(m.maps.roughnessTexture, m.maps.metallicTexture);
    EXPECT_EQ(m.maps.metallicChannel, 2);
    EXPECT_EQ(m.maps.roughnessChannel, 1);
}

// metal_rough_texture.gltf: factors 1 and a metallicRoughnessTexture whose left half holds
// (metallic 1, roughness 128/255) and right half (0, 204/255) in B and G. Each half renders as the
// same scene with the texture removed and those factors set (paired pixels: mean difference within
// 5 standard errors, plus 1e-4 of the level for the texel's float rounding), and the halves differ.
TEST(MetallicRoughnessTexture, EachHalfShadesAsItsConstantMaterial) {
    Scene s = loadScene(assetScene("metal_rough_texture.gltf"));
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    ASSERT_NO_FATAL_FAILURE(expectGltfMetallicRoughness(*m));
    constexpr int kSpp = 8;
    Film textured = render(s, kSpp);
    struct Half {
        int x0, x1;
        float metallic, roughness;
    };
    // Columns near the texture's split (x = 0, column 32) are left out: their footprint mixes.
    const Half halves[2] = {{0, 28, 1.0f, 128 / 255.0f}, {36, kSize, 0.0f, 204 / 255.0f}};
    double levels[2];
    for (int h = 0; h < 2; ++h) {
        Scene constant = loadScene(assetScene("metal_rough_texture.gltf"));
        for (Material& c : constant.materials) {
            if (c.kind != MaterialKind::Principled) continue;
            c.maps.metallicTexture = c.maps.roughnessTexture = -1;
            c.metallic = halves[h].metallic, c.roughness = halves[h].roughness;
        }
        Paired p = paired(textured, render(constant, kSpp), halves[h].x0, halves[h].x1);
        EXPECT_GT(p.level, 0.01) << "half " << h << " is lit";
        EXPECT_NEAR(p.mean, 0.0, 5 * p.se + 1e-4 * p.level) << "half " << h;
        levels[h] = p.level;
    }
    // The halves differ (measured 15 %: the metal's against the dielectric's diffuse and highlight;
    // 8 spp over these columns puts each level's noise below 1 %).
    EXPECT_GT(std::abs(levels[0] - levels[1]), 0.1 * std::max(levels[0], levels[1]));
}

// .kiln: metallic-roughness-texture beside base-color-texture, glTF's channel layout, data (not
// sRGB-decoded); a missing file is an error naming it.
TEST(MetallicRoughnessTexture, KilnAttribute) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.obj",
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    std::filesystem::copy_file(assetScene("metal_rough_halves.png"), dir / "mr.png");
    test::writeFile(dir / "t.kiln",
                    "<kiln-scene>\n"
                    "  <material name=\"p\" kind=\"principled\" metallic=\"0.5\" roughness=\"1\" "
                    "metallic-roughness-texture=\"mr.png\"/>\n"
                    "  <mesh file=\"quad.obj\" material=\"p\"/>\n"
                    "</kiln-scene>\n");
    Scene s = loadScene((dir / "t.kiln").string());
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    ASSERT_NO_FATAL_FAILURE(expectGltfMetallicRoughness(*m));
    EXPECT_FLOAT_EQ(m->metallic, 0.5f);
    test::writeFile(dir / "missing.kiln",
                    "<kiln-scene><material name=\"p\" kind=\"principled\" "
                    "metallic-roughness-texture=\"nope.png\"/></kiln-scene>\n");
    test::expectError((dir / "missing.kiln").string(), "nope.png not found");
}

// emissive.gltf (tools/make_asset_scenes.py): the panel's texture is code 255 in its top half and
// 128 in its bottom half (sRGB), times emissiveFactor 1 and KHR_materials_emissive_strength 4,
// which Assimp 5.2 does not hand over and kiln reads from the file.
constexpr float kStrength = 4.0f;

TEST(EmissiveTexture, PanelShowsItsTexturesHalves) {
    Scene s = loadScene(assetScene("emissive.gltf"));
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const Material* panel = test::findMaterial(s, MaterialKind::Principled, 1);
    ASSERT_TRUE(panel);
    EXPECT_EQ(panel->emission, Color(kStrength));
    ASSERT_GE(panel->maps.emissionTexture, 0);
    AovRequest aovs;
    aovs.add(AovKind::Emission);
    Film f = render(s, 4, PathOptions{}, aovs);
    // The light seen directly: each half's texel times the factor, the same in every pixel of a
    // half (mean within 5 standard errors of its pixels' spread, plus 1e-4 of it: the lookup's
    // rounding). Columns 44.. are panel; rows 30..33 straddle the split.
    size_t channel = test::aovChannel(f, "emission.G");
    auto half = [&](int y0, int y1) {
        double sum = 0, sum2 = 0;
        int n = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = 44; x < kSize; ++x) {
                double v = f.aov(x, y, channel);
                sum += v, sum2 += v * v, ++n;
            }
        double mean = sum / n;
        return std::pair(mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n));
    };
    auto [top, topSe] = half(0, 30);
    auto [bottom, bottomSe] = half(34, kSize);
    EXPECT_NEAR(top, kStrength * 1.0, 5 * topSe + 1e-4 * top);
    double dark = kStrength * srgbToLinear(128 / 255.0f);
    EXPECT_NEAR(bottom, dark, 5 * bottomSe + 1e-4 * dark);
    EXPECT_GT(top / bottom, 4.0);  // the pattern, not a flat light
}

// The textured panel is the floor's only light. Light sampling alone and MIS with BSDF sampling
// agree on the floor (paired pixels, mean difference within 5 standard errors) only if a sampled
// point on the panel emits what a ray hitting it sees: the texture at that point.
TEST(EmissiveTexture, NeeAndMisAgreeOnATexturedEmitter) {
    Scene s = loadScene(assetScene("emissive.gltf"));
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].kind, LightKind::MeshEmitter);
    auto renderWith = [&](DirectSampling sampling) {
        PathOptions o;
        o.sampling = sampling;
        o.maxDepth = 1;
        return render(s, 32, o);
    };
    Film mis = renderWith(DirectSampling::Mis), light = renderWith(DirectSampling::Light);
    Paired p = paired(mis, light, 0, 38);  // the floor
    EXPECT_GT(p.level, 0.05) << "the panel lights the floor";
    EXPECT_NEAR(p.mean, 0.0, 5 * p.se + 1e-6);
    // Its top half is the brighter: the floor's upper rows are lit more than its lower ones.
    double upper = 0, lower = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 20; x < 38; ++x)
            upper += luminance(light.pixel(x, y)),
                lower += luminance(light.pixel(x, kSize - 1 - y));
    EXPECT_GT(upper, 1.5 * lower);
}

// The panel of emissive.gltf made half transparent (glTF BLEND, alpha 0.5): rays hitting it stop
// with probability 0.5, so a light sample on it must carry half its radiance. With light sampling
// alone and direct light only, every floor pixel draws the same points as the opaque panel's render
// and must be exactly half as bright (to float rounding); MIS agrees with light sampling.
TEST(EmissiveTexture, ABlendedEmitterLightsByItsCoverage) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file(assetScene("emissive_halves.png"), dir / "emissive_halves.png");
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(assetScene("emissive.gltf")));
    for (auto& m : doc["materials"])
        if (m["name"] == "panel") {
            m["alphaMode"] = "BLEND";
            m["pbrMetallicRoughness"]["baseColorFactor"][3] = 0.5;
        }
    Scene blended = loadScene(test::writeFile(dir / "blended.gltf", doc.dump()));
    Scene opaque = loadScene(assetScene("emissive.gltf"));
    PathOptions o;
    o.maxDepth = 1;
    o.sampling = DirectSampling::Light;
    Film half = render(blended, 16, o), whole = render(opaque, 16, o);
    double worst = 0, level = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < 38; ++x) {
            double h = luminance(half.pixel(x, y)), w = luminance(whole.pixel(x, y));
            worst = std::max(worst, std::abs(h - 0.5 * w) / std::max(w, 1e-3));
            level += w / (kSize * 38);
        }
    EXPECT_GT(level, 0.05) << "the panel lights the floor";
    EXPECT_LT(worst, 1e-5) << "the floor lit by a half-covered panel is half as bright";
    o.sampling = DirectSampling::Mis;
    Paired p = paired(render(blended, 32, o),
                      render(blended, 32,
                             [&] {
                                 PathOptions l = o;
                                 l.sampling = DirectSampling::Light;
                                 return l;
                             }()),
                      0, 38);
    EXPECT_NEAR(p.mean, 0.0, 5 * p.se + 1e-6);
}

// glTF occlusionTexture (Assimp 5.2's LIGHTMAP slot) and FBX ambient occlusion: a path tracer
// computes occlusion, so the map is named in one warning per material that has one.
TEST(OcclusionTexture, NamedOncePerMaterial) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file(assetScene("emissive_halves.png"), dir / "emissive_halves.png");
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(assetScene("emissive.gltf")));
    for (auto& m : doc["materials"]) m["occlusionTexture"] = {{"index", 0}, {"strength", 0.5}};
    std::string path = test::writeFile(dir / "occluded.gltf", doc.dump());
    Scene s = loadScene(path);
    EXPECT_EQ(test::warningsNaming(s,
                                   "occlusionTexture 'emissive_halves.png' ignored: kiln "
                                   "computes occlusion"),
              2);
    EXPECT_EQ(test::warningsNaming(s, "material 'floor': occlusionTexture"), 1);
    EXPECT_EQ(test::warningsNaming(s, "material 'panel': occlusionTexture"), 1);
    EXPECT_EQ(test::warningsNaming(s, "lightmap"), 0);
    EXPECT_EQ(s.warnings.size(), 2u) << s.warnings.front();

    Scene fbx = loadScene("/usr/share/assimp/models/FBX/maxPbrMaterial_metalRough.fbx");
    EXPECT_EQ(test::warningsNaming(fbx, "occlusionTexture 'Textures\\occlusion.png' ignored"), 1);
    EXPECT_EQ(test::warningsNaming(fbx, "ambient-occlusion"), 0);
}

// Khronos' ClearCoatTest through Assimp: the metallic-roughness texture is read (not named as an
// ignored metallic, roughness or unknown map) and the label's emissive texture is used.
TEST(MaterialTextures, ClearCoatSampleReadsItsMetallicRoughnessAndEmissiveMaps) {
    Scene s = loadScene("/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf");
    for (const char* dropped : {"metallic map", "roughness map", "unknown use", "emissive map"})
        EXPECT_EQ(test::warningsNaming(s, dropped), 0) << dropped;
    int metalRough = 0, emissive = 0;
    for (const Material& m : s.materials) {
        metalRough += m.maps.metallicTexture >= 0;
        emissive += m.maps.emissionTexture >= 0;
    }
    EXPECT_GE(metalRough, 1);
    EXPECT_EQ(emissive, 1);
}

// metal_rough_halves.png (64 x 64): left half (x < 32) B = 1, right half B = 0. At s = 1.25 a
// repeating lookup reads s = 0.25 (left), a clamped one the right edge, a mirrored one s = 0.75
// (right), and at s = 1.75 the mirror reads s = 0.25 (left); black reads nothing.
TEST(TextureWrap, LookupsOutsideTheUnitSquare) {
    TextureSet set;
    TextureSource source;
    source.name = assetScene("metal_rough_halves.png");
    source.encoding = TextureEncoding::Data;
    int id = set.add(source);
    auto blue = [&](float s, TextureWrap wrap) {
        return set.lookupChannel(id, 2, s, 0.5f, 0.0f, {wrap, TextureWrap::Repeat});
    };
    EXPECT_FLOAT_EQ(blue(0.25f, TextureWrap::Repeat), 1.0f);
    EXPECT_FLOAT_EQ(blue(1.25f, TextureWrap::Repeat), 1.0f);
    EXPECT_FLOAT_EQ(blue(1.25f, TextureWrap::Clamp), 0.0f);
    EXPECT_FLOAT_EQ(blue(1.25f, TextureWrap::Mirror), 0.0f);
    EXPECT_FLOAT_EQ(blue(1.75f, TextureWrap::Mirror), 1.0f);
    EXPECT_FLOAT_EQ(blue(-0.25f, TextureWrap::Clamp), 1.0f);
    Color black = set.lookup(id, 1.25f, 0.5f, 0.0f, {TextureWrap::Black, TextureWrap::Repeat});
    EXPECT_EQ(black, Color(0.0f));
    // t wraps on its own: clamped on t, repeating on s.
    Color c = set.lookup(id, 1.25f, 1.5f, 0.0f, {TextureWrap::Repeat, TextureWrap::Clamp});
    EXPECT_FLOAT_EQ(c.z, 1.0f);
}

// emissive.gltf with the panel's emissiveTexture read through KHR_texture_transform scale (1, 2)
// and a sampler: the camera sees the panel's v in [0.2, 0.8], so v' = 2 v runs 0.4 .. 1.6, leaving
// the texture at row 32. Rows 36..54 (v' in 1.1 .. 1.45) are bright (v' - 1 < 0.5) when it
// repeats, dark when clamped to its last row or mirrored (2 - v' > 0.5); rows 60..63 (v' > 1.53)
// are bright only mirrored (2 - v' < 0.5).
TEST(TextureWrap, GltfSamplerWrapsTheEmissiveTexture) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file(assetScene("emissive_halves.png"), dir / "emissive_halves.png");
    const float bright = kStrength, dark = kStrength * srgbToLinear(128 / 255.0f);
    struct Case {
        int gl;  // glTF wrapT
        TextureWrap wrap;
        float middle, bottom;  // emission in rows 36..54 and 60..63
    };
    for (const Case& c : {Case{10497, TextureWrap::Repeat, bright, dark},
                          Case{33071, TextureWrap::Clamp, dark, dark},
                          Case{33648, TextureWrap::Mirror, dark, bright}}) {
        nlohmann::json doc = nlohmann::json::parse(std::ifstream(assetScene("emissive.gltf")));
        doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", c.gl}}};
        doc["textures"][0]["sampler"] = 0;
        doc["extensionsUsed"].push_back("KHR_texture_transform");
        doc["materials"][1]["emissiveTexture"]["extensions"] = {
            {"KHR_texture_transform", {{"scale", {1, 2}}}}};
        Scene s = loadScene(test::writeFile(dir / "wrapped.gltf", doc.dump()));
        const Material* panel = test::findMaterial(s, MaterialKind::Principled, 1);
        ASSERT_TRUE(panel);
        EXPECT_EQ(panel->maps.emissionUv.wrap.s, TextureWrap::Clamp);
        EXPECT_EQ(panel->maps.emissionUv.wrap.t, c.wrap);
        AovRequest aovs;
        aovs.add(AovKind::Emission);
        Film f = render(s, 1, PathOptions{}, aovs);
        size_t channel = test::aovChannel(f, "emission.G");
        for (int x = 44; x < kSize; x += 4) {
            for (int y = 36; y <= 54; y += 3)
                EXPECT_NEAR(f.aov(x, y, channel), c.middle, 1e-3f * bright) << x << "," << y;
            for (int y = 60; y < kSize; ++y)
                EXPECT_NEAR(f.aov(x, y, channel), c.bottom, 1e-3f * bright) << x << "," << y;
        }
    }
}

// A textured override material (--material-override FILE, and a .kiln <override material>)
// brings its own texture sources: its ids used to index the overridden scene's sources (the
// checker, or past their end).
TEST(MaterialTextures, OverrideMaterialKeepsItsTextures) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file(assetScene("metal_rough_halves.png"), dir / "mr.png");
    std::string mats = test::writeFile(
        dir / "mats.kiln",
        "<kiln-scene><material name=\"p\" kind=\"principled\" base-color-texture=\"mr.png\" "
        "metallic-roughness-texture=\"mr.png\"/></kiln-scene>\n");
    std::string include = test::writeFile(
        dir / "include.kiln",
        "<kiln-scene><material name=\"p\" kind=\"principled\" base-color-texture=\"mr.png\" "
        "metallic-roughness-texture=\"mr.png\"/><include file=\"" +
            assetScene("textured.gltf") + "\"><override material=\"p\"/></include></kiln-scene>\n");
    LoadOptions byFlag;
    byFlag.materialOverride = mats;
    for (const Scene& s : {loadScene(assetScene("textured.gltf"), byFlag), loadScene(include)}) {
        ASSERT_EQ(s.meshes.size(), 1u);
        const Material* m = &s.materials[s.meshes[0].materialOf(0)];  // the quad's
        EXPECT_EQ(m->name, "p");
        for (int id : {m->albedoTexture, m->maps.metallicTexture}) {
            ASSERT_GE(id, 0);
            ASSERT_LT(size_t(id), s.textureSources.size());
            EXPECT_EQ(s.textureSources[size_t(id)].name, (dir / "mr.png").string());
        }
        EXPECT_EQ(s.textureSources[size_t(m->maps.metallicTexture)].encoding,
                  TextureEncoding::Data);
    }
}

}  // namespace
}  // namespace kiln
