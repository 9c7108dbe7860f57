// A principled material's metallic-roughness, emissive and occlusion textures and the glTF sampler
// wrap modes (scenes/assets, written by tools/make_asset_scenes.py): each texture changes shading
// as the constant material it stands for would, and what kiln does not read is named once.
#include "renderer/accel/accelerator.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr int kSize = 64;  // the asset scenes' camera sees x, y in [-1, 1]: 32 pixels a unit

std::string assetScene(const std::string& name) { return test::repo("scenes/assets/" + name); }

Film render(const Scene& s, int spp, const PathOptions& path = {}) {
    auto accel = makeEmbreeAccelerator(s);
    return test::renderJob(s, *accel, test::jobOptions(kSize, kSize, spp, path));
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
    EXPECT_GT(std::abs(levels[0] - levels[1]), 0.2 * std::max(levels[0], levels[1]));
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

}  // namespace
}  // namespace kiln
