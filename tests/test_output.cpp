// EXR layers and metadata, the beauty = emission + direct + indirect identity, OCIO views, heat
// map.
#include <OpenImageIO/imageio.h>

#include "color/chromaticities.h"
#include "color/image_output.h"
#include "integrators/path.h"
#include "renderer/render_loop.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

Film render(const std::string& scenePath, const AovRequest& aovs, int maxDepth = 5, int spp = 8) {
    Scene s = loadScene(scenePath);
    auto accel = makeEmbreeAccelerator(s);
    PathOptions opt;
    opt.maxDepth = maxDepth;
    return test::renderJob(s, *accel, test::jobOptions(48, 36, spp, opt, aovs));
}

size_t channel(const Film& f, const std::string& name) { return test::aovChannel(f, name); }

Color layer(const Film& f, int x, int y, const std::string& name) {
    return Color(f.aov(x, y, channel(f, name + ".R")), f.aov(x, y, channel(f, name + ".G")),
                 f.aov(x, y, channel(f, name + ".B")));
}

void expectClose(const Color& a, const Color& b, const std::string& what) {
    float tol = 1e-5f * std::max(1.0f, maxComponent(abs(a)));
    EXPECT_LE(maxComponent(abs(a - b)), tol) << what << ": " << a.x << " " << a.y << " " << a.z
                                             << " vs " << b.x << " " << b.y << " " << b.z;
}

// Every lobe layer of one kind of light (direct_ or indirect_).
Color lobeSum(const Film& f, int x, int y, const std::string& prefix) {
    Color sum(0.0f);
    for (const char* lobe : {"diffuse", "specular", "transmission", "subsurface", "volume"})
        sum += layer(f, x, y, prefix + lobe);
    return sum;
}

// The sum of a layer's channels over the image.
double layerTotal(const Film& f, const std::string& name) {
    double total = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            Color c = layer(f, x, y, name);
            total += double(c.x) + c.y + c.z;
        }
    return total;
}

TEST(Aovs, BeautyIsEmissionPlusDirectPlusIndirectAndTheSplitsAddUp) {
    for (const std::string& scene :
         {test::cs184("sky/CBspheres.dae"), test::cs184("sky/CBbunny_microfacet_cu.dae"),
          test::cs184("sky/bunny.dae"), test::repo("scenes/cornell.dae"),
          test::repo("scenes/principled_lobes/glass.kiln"),
          test::repo("scenes/principled_lobes/sheen.kiln"),
          // Media and subsurface walks (the plan's media specialisation).
          test::repo("scenes/coloured_glass.kiln"), test::repo("scenes/lucy_subsurface.kiln")}) {
        Film f = render(scene, AovRequest::parse("all", 5));
        double total = 0;
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) {
                Color e = layer(f, x, y, "emission"), d = layer(f, x, y, "direct"),
                      i = layer(f, x, y, "indirect");
                expectClose(f.pixel(x, y), e + d + i, scene + " beauty");
                expectClose(d, lobeSum(f, x, y, "direct_"), scene + " direct lobes");
                expectClose(i, lobeSum(f, x, y, "indirect_"), scene + " indirect lobes");
                Color bounces(0.0f);
                for (int b = 1; b <= 5; ++b)
                    bounces += layer(f, x, y, "bounce" + std::to_string(b));
                expectClose(d + i, bounces, scene + " bounces");
                total += luminance(d) + luminance(i);
            }
        EXPECT_GT(total, 0.0) << scene;  // the identity is not vacuous
    }
}

TEST(Aovs, GlassSceneHasTransmissionAndSpecularLight) {
    Film f = render(test::cs184("sky/CBspheres.dae"),
                    AovRequest::parse("direct_specular,indirect_transmission", 5), 5, 16);
    double spec = 0, trans = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            spec += f.aov(x, y, 0) + f.aov(x, y, 1) + f.aov(x, y, 2);
            trans += f.aov(x, y, 3) + f.aov(x, y, 4) + f.aov(x, y, 5);
        }
    EXPECT_GT(trans, 0.0);  // light seen through the glass sphere: two refractions, so indirect
    EXPECT_GT(spec,
              0.0);  // the ceiling light seen in the mirror sphere: one specular bounce, direct
}

// Principled transmission: light seen through the glass bunnies and the thin pane counts as
// transmission (it reaches the camera after a refraction: indirect).
TEST(Aovs, PrincipledTransmissionIsTransmissionLight) {
    Film f = render(test::repo("scenes/principled_lobes/glass.kiln"),
                    AovRequest::parse("indirect_transmission", 5), 5, 8);
    double indirect = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x)
            for (int c = 0; c < 3; ++c) indirect += f.aov(x, y, c);
    EXPECT_GT(indirect, 0.0);
}

// Light that left the first surface through a random walk is subsurface light (Cycles'
// Subsurface passes), light scattered first in a medium is volume light (its Volume passes); a
// scene without either has none.
TEST(Aovs, SubsurfaceAndVolumeLightHaveLayersOfTheirOwn) {
    const AovRequest request = AovRequest::parse("all", 5);
    Film sss = render(test::repo("scenes/lucy_subsurface.kiln"), request, 5, 8);
    EXPECT_GT(layerTotal(sss, "direct_subsurface"), 0.0);
    EXPECT_GT(layerTotal(sss, "indirect_subsurface"), 0.0);
    EXPECT_EQ(layerTotal(sss, "direct_volume"), 0.0);
    // Fog behind an index-matched boundary: camera rays scatter first in the medium.
    auto dir = test::scratchDir();
    test::writeTetrahedronObj(dir / "box.obj");
    Film fog = render(test::writeFile(dir / "fog.kiln",
                                      "<kiln-scene><medium name=\"fog\" kind=\"homogeneous\" "
                                      "sigma-a=\"0.1 0.2 0.3\" sigma-s=\"2 2 2\"/>"
                                      "<mesh file=\"box.obj\" interior=\"fog\"/>"
                                      "<light kind=\"ambient\" radiance=\"1 1 1\"/></kiln-scene>"),
                      request, 5, 8);
    EXPECT_GT(layerTotal(fog, "direct_volume"), 0.0);
    EXPECT_GT(layerTotal(fog, "indirect_volume"), 0.0);
    EXPECT_EQ(layerTotal(fog, "direct_subsurface"), 0.0);
    for (int y = 0; y < fog.height(); ++y)  // still a complete split
        for (int x = 0; x < fog.width(); ++x) {
            expectClose(layer(fog, x, y, "direct"), lobeSum(fog, x, y, "direct_"), "fog direct");
            expectClose(layer(fog, x, y, "indirect"), lobeSum(fog, x, y, "indirect_"), "fog");
        }
    Film glass = render(test::cs184("sky/CBspheres.dae"), request, 5, 8);
    for (const char* name :
         {"direct_subsurface", "indirect_subsurface", "direct_volume", "indirect_volume"})
        EXPECT_EQ(layerTotal(glass, name), 0.0) << name;
}

TEST(Aovs, RequestParsing) {
    EXPECT_TRUE(AovRequest::parse("none", 5).mask == 0);
    AovRequest all = AovRequest::parse("all", 3);
    for (uint32_t k = 0; k < uint32_t(AovKind::Count); ++k) EXPECT_TRUE(all.has(AovKind(k))) << k;
    EXPECT_EQ(all.bounceLayers, 3);
    EXPECT_THROW(AovRequest::parse("direct,sparkle", 5), std::invalid_argument);
    AovLayout none(AovRequest::parse("none", 5));
    EXPECT_TRUE(none.channels().empty());  // nothing requested: nothing accumulated
}

TEST(ExrOutput, ChannelsTypesAndMetadataRoundTrip) {
    Film f =
        render(test::cs184("sky/CBspheres.dae"), AovRequest::parse("default,P,primid,objectid", 5));
    auto dir = test::scratchDir();
    for (bool half : {false, true}) {
        std::string path = (dir / (half ? "half.exr" : "float.exr")).string();
        ExrOptions opt;
        opt.half = half;
        opt.compression = half ? ExrCompression::Piz : ExrCompression::Zip;
        writeExr(path, f, {{"spp", "8"}, {"seed", "0"}, {"integrator", "path"}}, opt);
        auto in = OIIO::ImageInput::open(path);
        ASSERT_TRUE(in);
        const OIIO::ImageSpec& spec = in->spec();
        auto type = [&](const std::string& name) {
            int i = spec.channelindex(name);
            EXPECT_GE(i, 0) << name;
            return i < 0 ? OIIO::TypeDesc() : spec.channelformat(i);
        };
        OIIO::TypeDesc colour = half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
        for (const char* c :
             {"R", "G", "B", "A", "emission.R", "direct.G", "indirect.B", "albedo.R", "N.X"})
            EXPECT_EQ(type(c), colour) << c;
        for (const char* c :
             {"P.X", "P.Y", "P.Z", "Z", "samples.X", "variance.V", "primid.X", "objectid.X"})
            EXPECT_EQ(type(c), OIIO::TypeDesc(OIIO::TypeDesc::FLOAT)) << c;
        EXPECT_EQ(spec.get_string_attribute("compression"), half ? "piz" : "zip");
        EXPECT_EQ(spec.get_int_attribute("kiln:spp"), 8);
        EXPECT_EQ(spec.get_string_attribute("kiln:colorspace"), "lin_rec709");
        EXPECT_NE(spec.get_string_attribute("Software").find("kiln"), std::string::npos);
        EXPECT_NE(spec.find_attribute("chromaticities"), nullptr);
        // Values come back: the sample counts exactly, the beauty to half precision.
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
        int n = spec.channelindex("samples.X"), r = spec.channelindex("R");
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) {
                size_t base = (size_t(y) * spec.width + x) * spec.nchannels;
                ASSERT_EQ(px[base + n], float(f.samples(x, y)));
                ASSERT_NEAR(px[base + r], f.pixel(x, y).x,
                            half ? 1e-3f * std::max(1.0f, f.pixel(x, y).x) : 0.0f);
            }
        // The command-line tools read it too.
        EXPECT_EQ(std::system(("oiiotool --info -v " + path + " > /dev/null").c_str()), 0);
        EXPECT_EQ(std::system(("exrheader " + path + " > /dev/null").c_str()), 0);
    }
}

TEST(ColourManagement, ViewsOfTheShippedConfig) {
    EXPECT_NEAR(displayTransform(0.18f, "sRGB", "Standard"), 0.4614f, 1e-4f);
    float prev = -1;
    for (float v : {0.0f, 0.01f, 0.05f, 0.18f, 0.5f, 1.0f, 4.0f, 16.0f}) {
        float aces = displayTransform(v, "sRGB", "ACES 1.0 SDR-video");
        EXPECT_GT(aces, prev) << v;  // monotonic
        EXPECT_LE(aces, 1.0f + 1e-4f) << v;
        prev = aces;
    }
    float grey = displayTransform(0.18f, "sRGB", "ACES 1.0 SDR-video");
    EXPECT_GT(grey, 0.3f);
    EXPECT_LT(grey, 0.5f);
    EXPECT_LT(displayTransform(1.0f, "sRGB", "ACES 1.0 SDR-video"),
              0.95f);  // the tone curve rolls off
    EXPECT_NO_THROW(checkColorConfig("sRGB", "Raw"));
    EXPECT_THROW(checkColorConfig("sRGB", "Filmic"), std::invalid_argument);
    EXPECT_THROW(checkColorConfig("P3", "Standard"), std::invalid_argument);
}

TEST(HeatMap, BlueFewRedManyWithALegend) {
    Film f(20, 10);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 20; ++x)
            for (int k = 0; k <= x; ++k) f.add(x, y, Color(1.0f));
    std::string path = (test::scratchDir() / "heat.png").string();
    writeSampleHeatMap(path, f);
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().width, 20);
    EXPECT_GT(in->spec().height, 10);  // the legend below the image
    std::vector<uint8_t> px(size_t(in->spec().width) * in->spec().height * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    auto at = [&](int x, int y, int c) { return px[(size_t(y) * 20 + x) * 3 + c]; };
    // OIIO's turbo map: fewest samples dark blue, the middle green, most dark red.
    EXPECT_GT(at(0, 0, 2), at(0, 0, 0));
    EXPECT_GT(at(0, 0, 2), at(0, 0, 1));
    EXPECT_GT(at(10, 0, 1), at(10, 0, 0));
    EXPECT_GT(at(10, 0, 1), at(10, 0, 2));
    EXPECT_GT(at(19, 0, 0), 100);
    EXPECT_LT(at(19, 0, 2), 10);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

TEST(ColourManagement, ChromaticitiesConvertToTheWorkingSpace) {
    Mat3 id = toWorkingSpace(kRec709D65);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(id[i][j], i == j ? 1.0 : 0.0, 1e-9);
    // ACES2065-1 (AP0, ACES white) to linear Rec.709 with Bradford adaptation: the published
    // matrix.
    Chromaticities ap0 = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f};
    Mat3 m = toWorkingSpace(ap0);
    const double expected[3][3] = {{2.52169, -1.13413, -0.38756},
                                   {-0.27648, 1.37272, -0.09624},
                                   {-0.01538, -0.15298, 1.16835}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(m[i][j], expected[i][j], 2e-3) << i << "," << j;
    // Whatever the primaries, the file's white stays white.
    Chromaticities d50 = {0.648447f, 0.330877f,  0.321187f, 0.597894f,
                          0.155901f, 0.0660563f, 0.345708f, 0.358541f};
    Mat3 c = toWorkingSpace(d50);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i][0] + c[i][1] + c[i][2], 1.0, 1e-6);
}

TEST(ColourManagement, EnvironmentMapsAreConvertedOnLoad) {
    // shared/envmaps/city.exr states D50-white chromaticities: its pixels must change on load.
    Scene s;
    Light env;
    env.kind = LightKind::Environment;
    env.environmentPath = test::shared("envmaps/city.exr");
    env.environmentImage =
        std::make_shared<const RgbImage>(readWorkingSpaceImage(env.environmentPath));
    s.lights.push_back(env);
    LightSet lights(s);
    auto in = OIIO::ImageInput::open(env.environmentPath);
    ASSERT_TRUE(in);
    std::vector<float> raw(size_t(in->spec().width) * in->spec().height * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, raw.data()));
    int w = in->spec().width, h = in->spec().height;
    // The most saturated pixel: grey ones keep their value (white stays white).
    int x = 0, y = 0;
    float best = -1;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            const float* p = &raw[(size_t(py) * w + px) * 3];
            float sat = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
            if (sat > best) best = sat, x = px, y = py;
        }
    Vec3 dir = EnvironmentMap{}.direction((x + 0.5f) / w, (y + 0.5f) / h);
    Color loaded = lights.escaped(0, dir, true);
    Color file(raw[(size_t(y) * w + x) * 3], raw[(size_t(y) * w + x) * 3 + 1],
               raw[(size_t(y) * w + x) * 3 + 2]);
    Mat3 m = toWorkingSpace(
        {0.648447f, 0.330877f, 0.321187f, 0.597894f, 0.155901f, 0.0660563f, 0.345708f, 0.358541f});
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(loaded[i], m[i][0] * file.x + m[i][1] * file.y + m[i][2] * file.z,
                    1e-4f * (1 + file[i]));
    EXPECT_GT(maxComponent(abs(loaded - file)), 1e-4f);
}

}  // namespace
}  // namespace kiln
