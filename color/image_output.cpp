#include "color/image_output.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/color.h>
#include <OpenImageIO/fmath.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "color/atomic_file.h"
#include "color/exr_colour_space.h"
#include "color/oiio_write.h"
#include "color/working_space.h"

namespace kiln {

// Every image goes through an AtomicFile: a unique temporary name, every write checked, fsync,
// rename.
void writeAtomically(const std::string& path, const std::string& format, OIIO::ImageSpec spec,
                     const OIIO::ImageBuf& buf, const char* what, OIIO::TypeDesc dataType) {
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
    const std::string colourSpace = spec.get_string_attribute("oiio:ColorSpace");
    if (format != "openexr" || colourSpace.empty()) {
        file.commit();
        return;
    }
    // The colour space into the header (exr_colour_space.h), through a second temporary.
    file.flush();
    AtomicFile stamped(path);
    stampExrColourSpace(file.tempPath(), stamped.tempPath(), colourSpace);
    stamped.commit();
}

namespace {

// Beauty RGB (or the denoised one), opaque (the preview's input).
OIIO::ImageBuf beautyBuffer(const Film& film, const std::vector<Color>* denoised) {
    OIIO::ImageSpec spec(film.width(), film.height(), 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A"};
    spec.alpha_channel = 3;
    OIIO::ImageBuf buf(spec);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            Color c = denoised ? (*denoised)[size_t(y) * size_t(film.width()) + size_t(x)]
                               : film.pixel(x, y);
            // Opaque: the preview shows the premultiplied beauty over black, as rendered.
            float px[4] = {c.x, c.y, c.z, 1.0f};
            buf.setpixel(x, y, px, 4);
        }
    return buf;
}

// OIIO's view of the config in force (made again when $OCIO names another).
OIIO::ColorConfig& colorConfig() {
    static std::string path;
    static std::unique_ptr<OIIO::ColorConfig> config;
    if (!config || path != colorConfigPath()) {
        path = colorConfigPath();
        config = std::make_unique<OIIO::ColorConfig>(path);
    }
    return *config;
}

// scene_linear -> display/view of a float RGB(A) buffer.
OIIO::ImageBuf toDisplay(const OIIO::ImageBuf& linear, const std::string& display,
                         const std::string& view, const std::string& look = "") {
    ColorSetup setup = checkColorConfig(display, view, look);
    OIIO::ImageBuf shown;
    if (!OIIO::ImageBufAlgo::ociodisplay(shown, linear, setup.display, setup.view,
                                         setup.sceneLinear, setup.look, false, "", "",
                                         &colorConfig()))
        throw std::runtime_error("colour transform failed: " + shown.geterror());
    return shown;
}

// The OpenImageIO writer for a file name's extension (png, jpeg, ...).
std::string formatOf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    return ext.empty() ? "png" : ext.substr(1);
}

}  // namespace

namespace {

const char* kCryptoLayers[2] = {"CryptoObject", "CryptoMaterial"};

bool hasCrypto(const Film& film, int type) {
    return film.layout().request().has(type == 0 ? AovKind::CryptoObject : AovKind::CryptoMaterial);
}

// Every channel the file holds, in order, with its stored type.
void addChannels(OIIO::ImageSpec& spec, const Film& film, const ExrOptions& options) {
    const AovRequest& request = film.layout().request();
    OIIO::TypeDesc colourType = options.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
    auto add = [&](const std::string& name, OIIO::TypeDesc type) {
        spec.channelnames.push_back(name);
        spec.channelformats.push_back(type);
    };
    for (const char* c : {"R", "G", "B", "A"}) add(c, colourType);
    spec.alpha_channel = 3;
    if (options.denoised)
        for (const char* c : {"noisy.R", "noisy.G", "noisy.B"}) add(c, colourType);
    for (const DenoisedLayer& layer : film.layout().denoisedLayers())
        if (options.denoisedLayers.count(layer.name))
            for (size_t k = 0; k < 3; ++k)
                add("noisy." + film.layout().channels()[layer.channel + k].name, colourType);
    for (const AovChannel& c : film.layout().channels())
        add(c.name, c.colour || c.name.rfind("N.", 0) == 0 ? colourType : OIIO::TypeDesc::FLOAT);
    if (request.has(AovKind::Depth))
        spec.z_channel = spec.nchannels, add("Z", OIIO::TypeDesc::FLOAT);
    if (request.has(AovKind::Samples)) add("samples.X", OIIO::TypeDesc::FLOAT);
    if (request.has(AovKind::Variance)) add("variance.V", OIIO::TypeDesc::FLOAT);
    for (int type = 0; type < 2; ++type)
        if (hasCrypto(film, type))
            for (int layer = 0; layer < kCryptoRanks / 2; ++layer)
                for (const char* c : {"R", "G", "B", "A"})
                    add(fmt::format("{}{:02d}.{}", kCryptoLayers[type], layer, c),
                        OIIO::TypeDesc::FLOAT);
    // Exact to float: kiln denoise reads them back.
    if (film.hasHalves())
        for (int h = 0; h < 2; ++h) {
            for (const std::string& name : halfBufferChannels(h)) add(name, OIIO::TypeDesc::FLOAT);
            for (const DenoisedLayer& layer : film.layout().denoisedLayers())
                for (const std::string& name : layerHalfChannels(h, layer.name))
                    add(name, OIIO::TypeDesc::FLOAT);
        }
    spec.nchannels = int(spec.channelnames.size());
}

// Per layout channel, the denoised layer image that holds its value in the EXR (nullptr, or no
// entries at all: the film's own value) and which of its components.
struct DenoisedChannels {
    std::vector<const std::vector<Color>*> image;
    std::vector<int> component;
    std::vector<size_t> noisy;  // the channels written again as noisy.*, in order
};

DenoisedChannels denoisedChannels(const Film& film, const ExrOptions& options) {
    DenoisedChannels d;
    d.image.assign(film.layout().channels().size(), nullptr);
    d.component.assign(d.image.size(), 0);
    for (const DenoisedLayer& layer : film.layout().denoisedLayers()) {
        auto it = options.denoisedLayers.find(layer.name);
        if (it == options.denoisedLayers.end()) continue;
        for (size_t k = 0; k < 3; ++k) {
            d.image[layer.channel + k] = it->second.get();
            d.component[layer.channel + k] = int(k);
            d.noisy.push_back(layer.channel + k);
        }
    }
    return d;
}

// One pixel's values in addChannels' order.
void gatherPixel(const Film& film, int x, int y, std::vector<float>& px, const ExrOptions& options,
                 const DenoisedChannels& layers) {
    const AovRequest& request = film.layout().request();
    const size_t at = size_t(y) * size_t(film.width()) + size_t(x);
    px.clear();
    Color c = film.pixel(x, y);
    if (options.denoised) {
        Color d = (*options.denoised)[at];
        px.insert(px.end(), {d.x, d.y, d.z, film.alpha(x, y), c.x, c.y, c.z});
    } else {
        px.insert(px.end(), {c.x, c.y, c.z, film.alpha(x, y)});
    }
    for (size_t a : layers.noisy) px.push_back(film.aov(x, y, a));
    for (size_t a = 0; a < film.layout().channels().size(); ++a)
        px.push_back(!layers.image.empty() && layers.image[a]
                         ? (*layers.image[a])[at][layers.component[a]]
                         : film.aov(x, y, a));
    if (request.has(AovKind::Depth)) px.push_back(film.depth(x, y));
    if (request.has(AovKind::Samples)) px.push_back(float(film.samples(x, y)));
    if (request.has(AovKind::Variance)) px.push_back(float(film.luminanceVariance(x, y)));
    for (int type = 0; type < 2; ++type)
        if (hasCrypto(film, type))
            for (auto [id, coverage] : film.cryptoRanks(x, y, type))
                px.push_back(id), px.push_back(coverage);
    if (film.hasHalves())
        for (int h = 0; h < 2; ++h) {
            float half[kHalfChannels];
            film.halfMean(x, y, h, half);
            px.insert(px.end(), half, half + kHalfChannels);
            px.push_back(float(film.halfSamples(x, y, h)));
            for (size_t l = 0; l < film.layout().denoisedLayers().size(); ++l) {
                film.layerHalfMean(x, y, h, l, half);
                px.insert(px.end(), half, half + kLayerHalfChannels);
            }
        }
}

// Integers as int (or double beyond int's range), other numbers as double: a reader gets numbers,
// not text to parse. Anything else stays a string.
void addMetadataValue(OIIO::ImageSpec& spec, const std::string& key, const std::string& value) {
    const char *first = value.data(), *last = value.data() + value.size();
    long long i = 0;
    if (auto [end, ec] = std::from_chars(first, last, i); ec == std::errc() && end == last) {
        if (i >= INT32_MIN && i <= INT32_MAX) return spec.attribute(key, int(i));
        if (std::llabs(i) < (1ll << 53)) {
            double d = double(i);
            return spec.attribute(key, OIIO::TypeDesc::DOUBLE, &d);
        }
    }
    double d = 0;
    if (auto [end, ec] = std::from_chars(first, last, d);
        ec == std::errc() && end == last && std::isfinite(d))
        return spec.attribute(key, OIIO::TypeDesc::DOUBLE, &d);
    spec.attribute(key, value);
}

void addCryptoMetadata(OIIO::ImageSpec& spec, const Film& film, const ExrOptions& options) {
    for (int type = 0; type < 2; ++type) {
        if (!hasCrypto(film, type)) continue;
        std::string prefix = "cryptomatte/" + cryptoLayerKey(kCryptoLayers[type]) + "/";
        spec.attribute(prefix + "name", kCryptoLayers[type]);
        spec.attribute(prefix + "hash", "MurmurHash3_32");
        spec.attribute(prefix + "conversion", "uint32_to_float32");
        auto manifest = options.cryptoManifests.find(kCryptoLayers[type]);
        if (manifest != options.cryptoManifests.end())
            spec.attribute(prefix + "manifest", manifest->second);
    }
}

void addMetadata(OIIO::ImageSpec& spec, const Film& film, const Metadata& metadata,
                 const ExrOptions& options) {
    spec.attribute("compression", toString(options.compression));
    spec.attribute("Software", options.software.empty() ? std::string("kiln ") + KILN_VERSION
                                                        : options.software);
    spec.attribute("kiln:version", KILN_VERSION);
    spec.attribute("kiln:colorspace", options.colorSpace);
    spec.attribute("oiio:ColorSpace", options.colorSpace);
    // The working space's primaries and white (Rec.709 and D65 in kiln's own config), as
    // OpenEXR's chromaticities attribute.
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8),
                   workingSpace().chromaticities.data());
    const AovRequest& request = film.layout().request();
    spec.attribute("kiln:alpha", request.transparent
                                     ? "coverage by non-emitting surfaces; background transparent"
                                     : "coverage by surfaces; colour premultiplied");
    if (request.has(AovKind::Depth)) {
        spec.attribute("kiln:depth", request.depth == DepthMode::CameraZ
                                         ? "camera-space z (along the view axis)"
                                         : "distance along the camera ray");
        spec.attribute("kiln:depth_sample", "nearest first hit of the pixel's samples");
        spec.attribute("kiln:depth_miss", "inf");
    }
    if (options.camera) {
        spec.attribute("worldToCamera", OIIO::TypeMatrix, options.camera->worldToCamera.data());
        spec.attribute("worldToNDC", OIIO::TypeMatrix, options.camera->worldToNDC.data());
    }
    addCryptoMetadata(spec, film, options);
    for (const auto& [key, value] : metadata) addMetadataValue(spec, "kiln:" + key, value);
}

}  // namespace

void writeExr(const std::string& path, const Film& film, const Metadata& metadata,
              const ExrOptions& options) {
    OIIO::ImageSpec spec(film.width(), film.height(), 0, OIIO::TypeDesc::FLOAT);
    // A render region is the data window inside the full image's display window.
    spec.x = film.originX(), spec.y = film.originY();
    spec.full_x = 0, spec.full_y = 0;
    spec.full_width = film.fullWidth(), spec.full_height = film.fullHeight();
    addChannels(spec, film, options);
    addMetadata(spec, film, metadata, options);

    // Fill in float; OIIO converts each channel to its format on write.
    OIIO::ImageSpec memSpec = spec;
    memSpec.channelformats.clear();
    memSpec.set_format(OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(memSpec);
    std::vector<float> px;
    const DenoisedChannels layers = denoisedChannels(film, options);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            gatherPixel(film, x, y, px, options, layers);
            buf.setpixel(x + film.originX(), y + film.originY(), px.data(), spec.nchannels);
        }
    writeAtomically(path, "openexr", spec, buf, "EXR");
}

std::vector<ExrLayer> exrLayers(const Film& film) {
    OIIO::ImageSpec spec(film.width(), film.height(), 0, OIIO::TypeDesc::FLOAT);
    addChannels(spec, film, {});
    std::vector<ExrLayer> layers;
    for (size_t c = 0; c < spec.channelnames.size(); ++c) {
        const std::string& full = spec.channelnames[c];
        size_t dot = full.rfind('.');
        std::string layer =
            dot == std::string::npos ? (full == "Z" ? "Z" : "") : full.substr(0, dot);
        if (layers.empty() || layers.back().name != layer) layers.push_back({layer, {}, c});
        layers.back().channels.push_back(dot == std::string::npos ? full : full.substr(dot + 1));
    }
    return layers;
}

void exrPixel(const Film& film, int x, int y, std::vector<float>& values) {
    gatherPixel(film, x, y, values, {}, {});
}

std::map<std::string, ExrAttribute> exrHeader(const Film& film, const Metadata& metadata,
                                              const ExrOptions& options) {
    OIIO::ImageSpec spec(film.width(), film.height(), 0, OIIO::TypeDesc::FLOAT);
    addMetadata(spec, film, metadata, options);
    std::map<std::string, ExrAttribute> header;
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
        const OIIO::TypeDesc t = p.type();
        ExrAttribute& value = header[p.name().string()];
        if (t == OIIO::TypeDesc::INT)
            value = p.get_int();
        else if (t == OIIO::TypeDesc::DOUBLE)
            value = *static_cast<const double*>(p.data());
        else if (t == OIIO::TypeDesc::FLOAT)
            value = double(p.get_float());
        else if (t == OIIO::TypeDesc::STRING)
            value = p.get_string();
        else if (t.basetype == OIIO::TypeDesc::FLOAT) {
            const float* v = static_cast<const float*>(p.data());
            value = std::vector<float>(v, v + size_t(p.nvalues()) * t.numelements() * t.aggregate);
        } else
            value = p.get_string();
    }
    return header;
}

void writePreview(const std::string& path, const Film& film, const std::string& display,
                  const std::string& view, float exposureStops, const std::string& look,
                  const std::vector<Color>* denoised) {
    OIIO::ImageBuf linear = beautyBuffer(film, denoised);
    if (exposureStops != 0)
        OIIO::ImageBufAlgo::mul(linear, linear, std::exp2(exposureStops));  // --exposure
    OIIO::ImageBuf shown = toDisplay(linear, display, view, look);
    OIIO::ImageSpec spec = shown.spec();
    // zlib's fastest level: the preview's deflate at libpng's default (6) was a fifth of a 1080p
    // frame's write time; level 1 takes under half as long for a file about a quarter larger
    // (docs/output.md).
    spec.attribute("png:compressionLevel", 1);
    writeAtomically(path, formatOf(path), spec, shown, "preview", OIIO::TypeDesc::UINT8);
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

}  // namespace

// OIIO's turbo colour map (dark blue few, green, dark red many) of a one-channel image of [0, 1]
// values.
std::vector<float> turbo(const std::vector<float>& t, int w, int h) {
    OIIO::ImageBuf src(OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT), (void*)t.data());
    OIIO::ImageBuf mapped = OIIO::ImageBufAlgo::color_map(src, 0, "turbo");
    if (mapped.has_error()) throw std::runtime_error("heat map: " + mapped.geterror());
    std::vector<float> rgb(size_t(w) * h * 3);
    mapped.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, rgb.data());
    // OIIO's maps are linear values; the PNG holds sRGB-encoded ones.
    for (float& v : rgb) v = OIIO::linear_to_sRGB(v);
    return rgb;
}

void writeSampleHeatMap(const std::string& path, const Film& film) {
    int w = film.width(), h = film.height();
    uint32_t lo = UINT32_MAX, hi = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            lo = std::min(lo, film.samples(x, y)), hi = std::max(hi, film.samples(x, y));
    // The legend: a gradient bar under the image with the range's ends written at its ends.
    int scale = std::max(1, w / 200), barH = 8 * scale, legendH = barH + 7 * scale;
    int H = h + legendH;
    std::vector<float> t(size_t(w) * H, 0.0f);
    float span = hi > lo ? float(hi - lo) : 1.0f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            t[size_t(y) * w + x] = (float(film.samples(x, y)) - float(lo)) / span;
    for (int y = h + scale; y < h + barH; ++y)
        for (int x = 0; x < w; ++x) t[size_t(y) * w + x] = float(x) / float(std::max(1, w - 1));
    std::vector<float> rgb = turbo(t, w, H);
    // Black around the bar, under the numbers.
    for (int y = h; y < H; ++y)
        if (y < h + scale || y >= h + barH)
            std::fill_n(&rgb[size_t(y) * w * 3], size_t(w) * 3, 0.0f);
    drawNumber(rgb, w, H, scale, h + barH + scale, lo, scale);
    std::string hiText = std::to_string(hi);
    drawNumber(rgb, w, H, w - int(hiText.size()) * 4 * scale, h + barH + scale, hi, scale);
    OIIO::ImageBuf buf(OIIO::ImageSpec(w, H, 3, OIIO::TypeDesc::FLOAT), rgb.data());
    // The colours are a display-referred code, not scene light: written as is.
    writeAtomically(path, "png", buf.spec(), buf, "heat map", OIIO::TypeDesc::UINT8);
}

float displayTransform(float linear, const std::string& display, const std::string& view) {
    OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf src(spec);
    float v[3] = {linear, linear, linear};
    src.setpixel(0, 0, v, 3);
    OIIO::ImageBuf dst = toDisplay(src, display, view);
    float out[3];
    dst.getpixel(0, 0, out, 3);
    return out[0];
}

}  // namespace kiln
