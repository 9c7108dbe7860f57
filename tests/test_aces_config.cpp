// A studio config whose scene_linear is ACEScg (defined by OCIO built-in transforms only): kiln
// renders in it, converting the linear Rec.709 colours it reads, so the render equals, within
// Monte Carlo noise, the default render converted to ACEScg by the 3x3 matrix; the EXR says so.
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>

#include "aces_config.h"
#include "color/texture.h"
#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace OCIO = OCIO_NAMESPACE;

struct Rgb {
    int width = 0, height = 0;
    std::vector<float> px;  // RGB interleaved
};

Rgb readRgb(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path;
    Rgb img{in->spec().width, in->spec().height, {}};
    img.px.resize(size_t(img.width) * img.height * 3);
    in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, img.px.data());
    return img;
}

// A saturated lat-long sky (linear Rec.709, no chromaticities stated): every channel matters.
std::string writeSky(const std::filesystem::path& path) {
    const int w = 32, h = 16;
    std::vector<float> px(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = &px[3 * (size_t(y) * w + x)];
            p[0] = x < w / 2 ? 1.5f : 0.05f, p[1] = y < h / 2 ? 0.9f : 0.1f, p[2] = 1.2f - p[0] / 2;
        }
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(out && out->open(path.string(), spec) &&
                out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
    return path.string();
}

// linear Rec.709 -> ACEScg, as the config's own processor states it.
std::array<float, 9> rec709ToAcescg(const std::string& configPath) {
    auto config = OCIO::Config::CreateFromFile(configPath.c_str());
    auto cpu = config->getProcessor("lin_rec709", "acescg")->getDefaultCPUProcessor();
    std::array<float, 9> m{};
    for (int c = 0; c < 3; ++c) {
        float rgb[3] = {0, 0, 0};
        rgb[c] = 1;
        cpu->applyRGB(rgb);
        for (int r = 0; r < 3; ++r) m[size_t(3 * r + c)] = rgb[r];
    }
    return m;
}

// Per channel, the mean of (a - expected) over its standard error: independent pixels, so the
// standard error comes from the differences' own spread.
std::array<double, 3> tStatistics(const Rgb& a, const std::vector<float>& expected) {
    std::array<double, 3> t{};
    const size_t n = a.px.size() / 3;
    for (size_t c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0;
        for (size_t i = 0; i < n; ++i) {
            double d = a.px[3 * i + c] - expected[3 * i + c];
            sum += d, sum2 += d * d;
        }
        double mean = sum / double(n), var = (sum2 / double(n) - mean * mean) / double(n - 1);
        t[c] = mean / std::sqrt(std::max(var, 1e-30));
    }
    return t;
}

std::string renderArgs(const std::string& sky, const std::filesystem::path& out, int seed) {
    return "render " + test::repo("scenes/cornell.dae") +
           " -r 48 36 -s 16 -q --material-override lambertian:0.6 --env " + sky + " --seed " +
           std::to_string(seed) + " -o " + out.string();
}

// Grey surfaces lit by a coloured sky: the image is linear in the sky's colours, so rendering in
// ACEScg equals converting the Rec.709 render (the paths' expectations, not their samples).
TEST(AcesConfig, RenderEqualsTheDefaultRenderConvertedToAcescg) {
    auto dir = test::scratchDir();
    std::string sky = writeSky(dir / "sky.exr");
    test::CliRun base = test::runKiln(renderArgs(sky, dir / "rec709", 1));
    ASSERT_EQ(base.code, 0) << base.err;
    std::string configPath = test::writeFile(dir / "aces.ocio", test::kAcesConfig);
    test::ScopedEnv ocio("OCIO", configPath);
    test::CliRun aces = test::runKiln(renderArgs(sky, dir / "acescg", 2) + " --look Brighter");
    ASSERT_EQ(aces.code, 0) << aces.err;
    Rgb d = readRgb(dir / "rec709.exr"), a = readRgb(dir / "acescg.exr");
    ASSERT_EQ(d.px.size(), a.px.size());
    std::array<float, 9> m = rec709ToAcescg(configPath);
    std::vector<float> converted(d.px.size());
    for (size_t i = 0; i < d.px.size(); i += 3)
        for (size_t r = 0; r < 3; ++r)
            converted[i + r] =
                m[3 * r] * d.px[i] + m[3 * r + 1] * d.px[i + 1] + m[3 * r + 2] * d.px[i + 2];
    // 4 standard errors: a false alarm about once in 16000 per channel.
    std::array<double, 3> t = tStatistics(a, converted);
    for (size_t c = 0; c < 3; ++c) EXPECT_LT(std::abs(t[c]), 4.0) << "channel " << c;
    // The test has the power to see a render left in Rec.709.
    std::array<double, 3> unconverted = tStatistics(a, d.px);
    EXPECT_GT(
        std::max({std::abs(unconverted[0]), std::abs(unconverted[1]), std::abs(unconverted[2])}),
        8.0);
    EXPECT_TRUE(std::filesystem::exists(dir / "acescg.png"));
}

// A constant w x h linear float EXR, with chromaticities when `stated` is given.
std::string writeLinearExr(const std::filesystem::path& path, std::array<float, 3> rgb,
                           const float* stated = nullptr) {
    const int w = 8, h = 8;
    std::vector<float> px;
    for (int i = 0; i < w * h; ++i) px.insert(px.end(), rgb.begin(), rgb.end());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    if (stated) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), stated);
    auto out = OIIO::ImageOutput::create(path.string());
    EXPECT_TRUE(out && out->open(path.string(), spec) &&
                out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
    return path.string();
}

// Linear colour textures reach the working space as environment maps do: a float EXR that states
// nothing is linear Rec.709 and is converted to ACEScg; one that states ACEScg's chromaticities is
// already there; a data map (normals, roughness) is never touched. Both texture paths: the
// converted tiled file in the cache and the image read whole (an unusable cache directory).
TEST(AcesConfig, LinearTexturesAreConvertedFromTheirStatedSpace) {
    auto dir = test::scratchDir();
    const float ap1D60[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    std::string rec709 = writeLinearExr(dir / "rec709.exr", {0.8f, 0.2f, 0.1f});
    std::string acescg = writeLinearExr(dir / "acescg.exr", {0.3f, 0.5f, 0.2f}, ap1D60);
    std::string configPath = test::writeFile(dir / "aces.ocio", test::kAcesConfig);
    std::array<float, 9> m = rec709ToAcescg(configPath);
    const std::string blocked = test::writeFile(dir / "a-file", "") + "/cache";
    for (std::string cache : {(dir / "cache").string(), blocked}) {
        test::ScopedEnv tx("KILN_TEXTURE_CACHE", cache);
        {
            TextureSet plain(16.0f);  // kiln's own config: nothing converted
            Color c = plain.lookup(plain.add({rec709, nullptr, "", TextureEncoding::Color}), 0.5f,
                                   0.5f, 0.0f);
            EXPECT_EQ(c, Color(0.8f, 0.2f, 0.1f)) << cache;
        }
        test::ScopedEnv ocio("OCIO", configPath);
        TextureSet set(16.0f);
        Color a = set.lookup(set.add({rec709, nullptr, "", TextureEncoding::Color}), 0.5f, 0.5f, 0);
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(
                a[r],
                m[size_t(3 * r)] * 0.8f + m[size_t(3 * r + 1)] * 0.2f + m[size_t(3 * r + 2)] * 0.1f,
                1e-4f)
                << cache << " channel " << r;
        Color b = set.lookup(set.add({acescg, nullptr, "", TextureEncoding::Color}), 0.5f, 0.5f, 0);
        EXPECT_NEAR(b.x, 0.3f, 2e-3f) << cache;  // the stated AP1 to 3 decimals, as in files
        EXPECT_NEAR(b.y, 0.5f, 2e-3f) << cache;
        EXPECT_NEAR(b.z, 0.2f, 2e-3f) << cache;
        Color d = set.lookup(set.add({rec709, nullptr, "", TextureEncoding::Data}), 0.5f, 0.5f, 0);
        EXPECT_EQ(d, Color(0.8f, 0.2f, 0.1f)) << cache;
    }
}

// The EXR names the working space: oiio:ColorSpace (which OIIO 2.4's writer drops: kiln adds it,
// exr_colour_space.h), kiln:colorspace and ACEScg's chromaticities (AP1, D60 white). So oiiotool
// --ociodisplay takes the file from acescg without being told.
TEST(AcesConfig, ExrStatesAcescgChromaticitiesAndName) {
    auto dir = test::scratchDir();
    test::ScopedEnv ocio("OCIO", test::writeFile(dir / "aces.ocio", test::kAcesConfig));
    test::CliRun r = test::runKiln("render " + test::repo("scenes/cornell.dae") +
                                   " -r 16 12 -s 1 -q -o " + (dir / "out").string());
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open((dir / "out.exr").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("kiln:colorspace"), "acescg");
    EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "acescg");
    const OIIO::ParamValue* chroma =
        in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
    ASSERT_TRUE(chroma);
    const float* c = static_cast<const float*>(chroma->data());
    const float ap1D60[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(c[i], ap1D60[i], 2e-3) << i;
}

}  // namespace
}  // namespace kiln
