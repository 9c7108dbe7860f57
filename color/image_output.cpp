#include "color/image_output.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "color/atomic_file.h"

namespace kiln {
namespace {

// Beauty RGBA only (the preview's input).
OIIO::ImageBuf beautyBuffer(const Film& film) {
    OIIO::ImageSpec spec(film.width(), film.height(), 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A"};
    spec.alpha_channel = 3;
    OIIO::ImageBuf buf(spec);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            Color c = film.pixel(x, y);
            float px[4] = {c.x, c.y, c.z, 1.0f};
            buf.setpixel(x, y, px, 4);
        }
    return buf;
}

OIIO::ColorConfig& colorConfig() {
    static OIIO::ColorConfig config(colorConfigPath());
    return config;
}

// The OpenImageIO writer for a file name's extension (png, jpeg, ...).
std::string formatOf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    return ext.empty() ? "png" : ext.substr(1);
}

// Every image goes through an AtomicFile: a unique temporary name, every write checked, fsync,
// rename. spec's pixel type is what the file stores (dataType: all channels, when given).
void writeAtomically(const std::string& path, const std::string& format, OIIO::ImageSpec spec,
                     const OIIO::ImageBuf& buf, const char* what,
                     OIIO::TypeDesc dataType = OIIO::TypeDesc::UNKNOWN) {
    auto out = OIIO::ImageOutput::create(format);
    if (!out) throw std::runtime_error(path + ": no " + format + " writer: " + OIIO::geterror());
    if (dataType != OIIO::TypeDesc::UNKNOWN) {
        spec.channelformats.clear();
        spec.set_format(dataType);
    }
    AtomicFile file(path);
    if (!out->set_ioproxy(file.proxy()) || !out->open(path, spec) || !buf.write(out.get()) ||
        !out->close())
        throw std::runtime_error(path + ": cannot write " + what + ": " + out->geterror() +
                                 buf.geterror());
    out.reset();
    file.commit();
}

}  // namespace

std::string colorConfigPath() {
    if (const char* env = std::getenv("OCIO"); env && *env) return env;
    return std::string(KILN_SOURCE_DIR) + "/color/config.ocio";
}

void writeExr(const std::string& path, const Film& film, const Metadata& metadata,
              const ExrOptions& options) {
    const AovLayout& layout = film.layout();
    bool samples = layout.request().has(AovKind::Samples),
         variance = layout.request().has(AovKind::Variance);
    int nc = 4 + int(layout.channels().size()) + int(samples) + int(variance);
    OIIO::ImageSpec spec(film.width(), film.height(), nc, OIIO::TypeDesc::FLOAT);
    // A render region is the data window inside the full image's display window.
    spec.x = film.originX(), spec.y = film.originY();
    spec.full_x = 0, spec.full_y = 0;
    spec.full_width = film.fullWidth(), spec.full_height = film.fullHeight();
    spec.channelnames = {"R", "G", "B", "A"};
    OIIO::TypeDesc colourType = options.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
    spec.channelformats.assign(4, colourType);
    for (const AovChannel& c : layout.channels()) {
        spec.channelnames.push_back(c.name);
        spec.channelformats.push_back(c.colour || c.name.rfind("N.", 0) == 0
                                          ? colourType
                                          : OIIO::TypeDesc(OIIO::TypeDesc::FLOAT));
    }
    if (samples)
        spec.channelnames.push_back("samples"),
            spec.channelformats.push_back(OIIO::TypeDesc::FLOAT);
    if (variance)
        spec.channelnames.push_back("variance"),
            spec.channelformats.push_back(OIIO::TypeDesc::FLOAT);
    spec.alpha_channel = 3;
    if (options.compression != "zip" && options.compression != "piz")
        throw std::runtime_error(path + ": unknown EXR compression '" + options.compression +
                                 "' (zip or piz)");
    spec.attribute("compression", options.compression);
    spec.attribute("Software", std::string("kiln ") + KILN_VERSION);
    spec.attribute("kiln:version", KILN_VERSION);
    spec.attribute("kiln:colorspace", "lin_rec709");
    spec.attribute("oiio:ColorSpace", "lin_rec709");
    // Rec.709 primaries and D65 white, as OpenEXR's chromaticities attribute.
    static const float chroma[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
    for (const auto& [key, value] : metadata) spec.attribute("kiln:" + key, value);

    // Fill in float; OIIO converts each channel to its format on write.
    OIIO::ImageSpec memSpec = spec;
    memSpec.channelformats.clear();
    memSpec.set_format(OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(memSpec);
    std::vector<float> px(static_cast<size_t>(nc));
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            Color c = film.pixel(x, y);
            px[0] = c.x, px[1] = c.y, px[2] = c.z, px[3] = 1.0f;
            size_t k = 4;
            for (size_t a = 0; a < layout.channels().size(); ++a) px[k++] = film.aov(x, y, a);
            if (samples) px[k++] = float(film.samples(x, y));
            if (variance) px[k++] = float(film.luminanceVariance(x, y));
            buf.setpixel(x + film.originX(), y + film.originY(), px.data(), nc);
        }
    writeAtomically(path, "openexr", spec, buf, "EXR");
}

void writePreview(const std::string& path, const Film& film, const std::string& display,
                  const std::string& view, float exposureStops) {
    OIIO::ImageBuf linear = beautyBuffer(film);
    if (exposureStops != 0)
        OIIO::ImageBufAlgo::mul(linear, linear, std::exp2(exposureStops));  // --exposure
    OIIO::ImageBuf shown;
    if (!OIIO::ImageBufAlgo::ociodisplay(shown, linear, display, view, "lin_rec709", "", false, "",
                                         "", &colorConfig()))
        throw std::runtime_error(path + ": colour transform failed: " + shown.geterror());
    writeAtomically(path, formatOf(path), shown.spec(), shown, "preview", OIIO::TypeDesc::UINT8);
}

namespace {

// A 3x5 bitmap font for the legend's digits.
constexpr uint16_t kDigits[10] = {0x7B6F, 0x2C97, 0x73E7, 0x73CF, 0x5BC9,
                                  0x79CF, 0x79EF, 0x7249, 0x7BEF, 0x7BCF};

void drawNumber(std::vector<float>& rgb, int w, int h, int x0, int y0, uint32_t value, int scale) {
    std::string text = std::to_string(value);
    for (char ch : text) {
        uint16_t g = kDigits[ch - '0'];
        for (int r = 0; r < 5; ++r)
            for (int c = 0; c < 3; ++c)
                if (g & (1 << (14 - (r * 3 + c))))
                    for (int sy = 0; sy < scale; ++sy)
                        for (int sx = 0; sx < scale; ++sx) {
                            int x = x0 + c * scale + sx, y = y0 + r * scale + sy;
                            if (x >= 0 && y >= 0 && x < w && y < h)
                                for (int k = 0; k < 3; ++k) rgb[(size_t(y) * w + x) * 3 + k] = 1.0f;
                        }
        x0 += 4 * scale;
    }
}

// Blue (few) through cyan, green, yellow to red (many).
Color heat(float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    float r = std::clamp(1.5f - std::abs(4 * t - 3), 0.0f, 1.0f);
    float g = std::clamp(1.5f - std::abs(4 * t - 2), 0.0f, 1.0f);
    float b = std::clamp(1.5f - std::abs(4 * t - 1), 0.0f, 1.0f);
    return {r, g, b};
}

}  // namespace

void writeSampleHeatMap(const std::string& path, const Film& film) {
    int w = film.width(), h = film.height();
    uint32_t lo = UINT32_MAX, hi = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            lo = std::min(lo, film.samples(x, y)), hi = std::max(hi, film.samples(x, y));
    // The legend: a gradient bar under the image with the range's ends written at its ends.
    int scale = std::max(1, w / 200), barH = 8 * scale, legendH = barH + 7 * scale;
    int H = h + legendH;
    std::vector<float> rgb(size_t(w) * H * 3, 0.0f);
    float span = hi > lo ? float(hi - lo) : 1.0f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Color c = heat((float(film.samples(x, y)) - float(lo)) / span);
            for (int k = 0; k < 3; ++k) rgb[(size_t(y) * w + x) * 3 + k] = c[k];
        }
    for (int y = h + scale; y < h + barH; ++y)
        for (int x = 0; x < w; ++x) {
            Color c = heat(float(x) / float(std::max(1, w - 1)));
            for (int k = 0; k < 3; ++k) rgb[(size_t(y) * w + x) * 3 + k] = c[k];
        }
    drawNumber(rgb, w, H, scale, h + barH + scale, lo, scale);
    std::string hiText = std::to_string(hi);
    drawNumber(rgb, w, H, w - int(hiText.size()) * 4 * scale, h + barH + scale, hi, scale);
    OIIO::ImageBuf buf(OIIO::ImageSpec(w, H, 3, OIIO::TypeDesc::FLOAT), rgb.data());
    // The colours are a display-referred code, not scene light: written as is.
    writeAtomically(path, "png", buf.spec(), buf, "heat map", OIIO::TypeDesc::UINT8);
}

void checkDisplayView(const std::string& display, const std::string& view) {
    namespace OCIO = OCIO_NAMESPACE;
    OCIO::ConstConfigRcPtr config;
    try {
        config = OCIO::Config::CreateFromFile(colorConfigPath().c_str());
    } catch (const OCIO::Exception& e) {
        throw std::invalid_argument(colorConfigPath() + ": cannot load OCIO config: " + e.what());
    }
    std::string displays, views;
    bool haveDisplay = false, haveView = false;
    for (int d = 0; d < config->getNumDisplays(); ++d) {
        std::string name = config->getDisplay(d);
        displays += (d ? ", " : "") + name;
        if (name != display) continue;
        haveDisplay = true;
        for (int v = 0; v < config->getNumViews(name.c_str()); ++v) {
            std::string vn = config->getView(name.c_str(), v);
            views += (v ? ", " : "") + vn;
            haveView |= vn == view;
        }
    }
    if (!haveDisplay)
        throw std::invalid_argument("unknown display '" + display + "' (known: " + displays + ")");
    if (!haveView)
        throw std::invalid_argument("display '" + display + "' has no view '" + view +
                                    "' (known: " + views + ")");
}

float displayTransform(float linear, const std::string& display, const std::string& view) {
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf src(spec), dst;
    float v[3] = {linear, linear, linear};
    src.setpixel(0, 0, v, 3);
    if (!OIIO::ImageBufAlgo::ociodisplay(dst, src, display, view, "lin_rec709", "", false, "", "",
                                         &colorConfig()))
        throw std::runtime_error("colour transform failed: " + dst.geterror());
    float out[3];
    dst.getpixel(0, 0, out, 3);
    return out[0];
}

}  // namespace kiln
