#include "color/image_output.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace kiln {
namespace {

OIIO::ImageBuf filmToBuffer(const Film& film, bool withSamples) {
    int channels = withSamples ? 5 : 4;
    OIIO::ImageSpec spec(film.width(), film.height(), channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A"};
    if (withSamples) spec.channelnames.push_back("samples");
    spec.alpha_channel = 3;
    OIIO::ImageBuf buf(spec);
    std::vector<float> px(static_cast<size_t>(channels));
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            Color c = film.pixel(x, y);
            px[0] = c.x, px[1] = c.y, px[2] = c.z, px[3] = 1.0f;
            if (withSamples) px[4] = float(film.samples(x, y));
            buf.setpixel(x, y, px.data(), channels);
        }
    return buf;
}

OIIO::ColorConfig& colorConfig() {
    static OIIO::ColorConfig config(colorConfigPath());
    return config;
}

}  // namespace

std::string colorConfigPath() {
    if (const char* env = std::getenv("OCIO"); env && *env) return env;
    return std::string(KILN_SOURCE_DIR) + "/color/config.ocio";
}

void writeExr(const std::string& path, const Film& film, const Metadata& metadata) {
    OIIO::ImageBuf buf = filmToBuffer(film, true);
    OIIO::ImageSpec& spec = buf.specmod();
    spec.attribute("compression", "zip");
    spec.attribute("Software", std::string("kiln ") + KILN_VERSION);
    spec.attribute("kiln:colorspace", "lin_rec709");
    // Rec.709 primaries and D65 white, as OpenEXR's chromaticities attribute.
    static const float chroma[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
    for (const auto& [key, value] : metadata) spec.attribute("kiln:" + key, value);
    std::string tmp = path + ".tmp";
    // Write under another name and rename, so a reader never sees a half-written EXR.
    if (!buf.write(tmp, OIIO::TypeDesc::FLOAT, "openexr")) {
        std::filesystem::remove(tmp);
        throw std::runtime_error(path + ": cannot write EXR: " + buf.geterror());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot move EXR into place: " + ec.message());
}

void writePreview(const std::string& path, const Film& film, const std::string& display, const std::string& view) {
    OIIO::ImageBuf linear = filmToBuffer(film, false);
    OIIO::ImageBuf shown;
    if (!OIIO::ImageBufAlgo::ociodisplay(shown, linear, display, view, "lin_rec709", "", false, "", "",
                                         &colorConfig()))
        throw std::runtime_error(path + ": colour transform failed: " + shown.geterror());
    std::string tmp = path + ".tmp" + std::filesystem::path(path).extension().string();
    if (!shown.write(tmp, OIIO::TypeDesc::UINT8)) {
        std::filesystem::remove(tmp);
        throw std::runtime_error(path + ": cannot write preview: " + shown.geterror());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot move preview into place: " + ec.message());
}

float displayTransform(float linear, const std::string& display, const std::string& view) {
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf src(spec), dst;
    float v[3] = {linear, linear, linear};
    src.setpixel(0, 0, v, 3);
    if (!OIIO::ImageBufAlgo::ociodisplay(dst, src, display, view, "lin_rec709", "", false, "", "", &colorConfig()))
        throw std::runtime_error("colour transform failed: " + dst.geterror());
    float out[3];
    dst.getpixel(0, 0, out, 3);
    return out[0];
}

}  // namespace kiln
