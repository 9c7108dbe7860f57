// readExrRgb (color/exr_rgb_input.h): an EXR environment map read with OpenEXR alone gives the
// image OpenImageIO's reader gives, bit for bit, or declines the file so the module reads it.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <thread>

#include "color/exr_rgb_input.h"
#include "color/exr_threads.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

void expectSameBits(const RgbImage& a, const RgbImage& b, const std::string& what) {
    ASSERT_EQ(a.width, b.width) << what;
    ASSERT_EQ(a.height, b.height) << what;
    ASSERT_EQ(a.pixels.size(), b.pixels.size()) << what;
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        differing += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(Color)) != 0;
    EXPECT_EQ(differing, 0u) << what;
}

// Read both ways: OpenEXR alone must take the file and agree with OpenImageIO.
void expectReadAsOiioReadsIt(const std::string& path) {
    std::optional<RgbImage> direct = readExrRgb(path);
    ASSERT_TRUE(direct) << path;
    expectSameBits(*direct, readWorkingSpaceImage(path), path);
}

// A 7x5 float image of distinct values (some negative, one NaN), one value per channel.
OIIO::ImageBuf pattern(const std::vector<std::string>& channels) {
    OIIO::ImageSpec spec(7, 5, int(channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = channels;
    OIIO::ImageBuf buf(spec);
    std::vector<float> values(size_t(7 * 5) * channels.size());
    for (size_t i = 0; i < values.size(); ++i) values[i] = 0.37f * float(i) - 3.1f;
    values[11] = std::numeric_limits<float>::quiet_NaN();
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, values.data());
    return buf;
}

std::string write(const fs::path& dir, const std::string& name, OIIO::ImageBuf buf,
                  OIIO::TypeDesc format = OIIO::TypeDesc::FLOAT) {
    const std::string path = (dir / name).string();
    EXPECT_TRUE(buf.write(path, format)) << buf.geterror();
    return path;
}

// A 7x5 float R, G, B file written by OpenEXR itself, its header changed by `edit` first.
void writeRgbWithOpenExr(const std::string& path, const std::function<void(Imf::Header&)>& edit) {
    Imf::Header header(7, 5);
    Imf::FrameBuffer frame;
    std::vector<float> values(7 * 5 * 3);
    for (size_t i = 0; i < values.size(); ++i) values[i] = 0.011f * float(i);
    for (int c = 0; c < 3; ++c) {
        const char* name = c == 0 ? "R" : c == 1 ? "G" : "B";
        header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() + c),
                                      3 * sizeof(float), 7 * 3 * sizeof(float)));
    }
    edit(header);
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(5);
}

TEST(ExrRgbInput, TheSharedEnvironmentMapsReadAsOpenImageIoReadsThem) {
    // city.exr states D50-white chromaticities: the conversion to the working space is compared
    // too.
    for (const char* map :
         {"city", "courtyard", "forest", "interior", "night", "studio", "sunrise", "sunset"})
        expectReadAsOiioReadsIt(test::shared(std::string("envmaps/") + map + ".exr"));
}

TEST(ExrRgbInput, HalfOffsetWindowsChromaticitiesLayersAndTilesReadAlike) {
    auto dir = test::scratchDir();
    // Half RGBA in a data window away from the origin, with D50 chromaticities.
    OIIO::ImageBuf rgba = pattern({"R", "G", "B", "A"});
    rgba.set_origin(3, -2);
    const float d50[8] = {0.648447f, 0.330877f,  0.321187f, 0.597894f,
                          0.155901f, 0.0660563f, 0.345708f, 0.358541f};
    rgba.specmod().attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), d50);
    expectReadAsOiioReadsIt(write(dir, "half.exr", rgba, OIIO::TypeDesc::HALF));
    // Layers and other unlayered channels beside R, G, B (OpenImageIO sorts R, G, B first).
    expectReadAsOiioReadsIt(
        write(dir, "layers.exr", pattern({"Z", "diffuse.R", "R", "A", "G", "B", "AB", "X"})));
    // Stated sRGB (OpenImageIO's writer leaves the attribute out, so OpenEXR writes it): decoded.
    const std::string srgb = (dir / "srgb.exr").string();
    writeRgbWithOpenExr(srgb, [](Imf::Header& header) {
        header.insert("oiio:ColorSpace", Imf::StringAttribute("sRGB"));
    });
    auto in = OIIO::ImageInput::open(srgb);
    ASSERT_TRUE(in);
    ASSERT_TRUE(isSrgbEncoded(in->spec()));
    expectReadAsOiioReadsIt(srgb);
    // Tiled and MIP-mapped, as maketx writes environment maps: the finest level.
    OIIO::ImageSpec config;
    const std::string tiled = (dir / "tiled.exr").string();
    ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxEnvLatl,
                                                 pattern({"R", "G", "B"}), tiled, config));
    expectReadAsOiioReadsIt(tiled);
}

TEST(ExrRgbInput, FilesItCannotReadExactlyAreLeftToTheModule) {
    auto dir = test::scratchDir();
    const std::vector<std::vector<std::string>> declined = {
        {"R", "G"},                               // no blue
        {"R", "G", "B", "Red"},                   // "Red" sorts between R and G
        {"R", "G", "B", "r"},                     // so does "r"
        {"Y", "RY", "BY"},                        // luminance-chroma
        {"diffuse.R", "diffuse.G", "diffuse.B"},  // layered only
    };
    for (const auto& channels : declined) {
        const std::string path = write(dir, "declined.exr", pattern(channels));
        EXPECT_FALSE(readExrRgb(path)) << channels.size() << " " << channels.back();
    }
    EXPECT_FALSE(
        readExrRgb(write(dir, "uint.exr", pattern({"R", "G", "B"}), OIIO::TypeDesc::UINT)));
    EXPECT_FALSE(
        readExrRgb(write(dir, "map.png", pattern({"R", "G", "B"}), OIIO::TypeDesc::UINT8)));
    EXPECT_FALSE(readExrRgb((dir / "missing.exr").string()));
    // OpenImageIO takes these attributes whatever their case (and a chromaticities of another
    // type), and refuses a file with any channel subsampled.
    const std::string lower = (dir / "lower.exr").string();
    writeRgbWithOpenExr(lower, [](Imf::Header& header) {
        header.insert("oiio:colorspace", Imf::StringAttribute("sRGB"));
    });
    EXPECT_FALSE(readExrRgb(lower));
    const std::string capital = (dir / "capital.exr").string();
    writeRgbWithOpenExr(capital, [](Imf::Header& header) {
        header.insert("Chromaticities", Imf::ChromaticitiesAttribute(Imf::Chromaticities()));
    });
    EXPECT_FALSE(readExrRgb(capital));
    const std::string subsampled = (dir / "subsampled.exr").string();
    writeRgbWithOpenExr(subsampled, [](Imf::Header& header) {
        header.channels().insert("A", Imf::Channel(Imf::HALF, 1, 5));
    });
    EXPECT_FALSE(readExrRgb(subsampled));
    // Cut short: OpenEXR's error leaves it to the module, whose message says what is wrong.
    const std::string whole = test::shared("envmaps/courtyard.exr");
    std::ifstream in(whole, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const fs::path cut = dir / "cut.exr";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), long(bytes.size() / 2));
    EXPECT_FALSE(readExrRgb(cut.string()));
    EXPECT_THROW(readWorkingSpaceImage(cut.string()), ImageReadError);
}

// OpenEXR's pool follows a render's -t (a farm task given 4 cores compresses on 4), and every core
// is only the default: an EXR opened after the render chose keeps its count.
TEST(ExrThreads, ARendersCountIsKeptAndEveryCoreIsOnlyTheDefault) {
    setExrThreads(1);
    EXPECT_EQ(Imf::globalThreadCount(), 1);
    exrThreadsOnEveryCore();
    EXPECT_EQ(Imf::globalThreadCount(), 1);
    setExrThreads(3);
    EXPECT_EQ(Imf::globalThreadCount(), 3);
    setExrThreads(0);
    EXPECT_EQ(Imf::globalThreadCount(), int(std::max(1u, std::thread::hardware_concurrency())));
}

}  // namespace
}  // namespace kiln
