// The film's EXR (image_output.h: writeExr, exrLayers, exrPixel, exrHeader), written with OpenEXR
// itself: a render that reads no image then never loads the image module and OpenImageIO's ~250
// libraries (image_module.h).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatVectorAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <stdexcept>

#include "color/atomic_file.h"
#include "color/exr_threads.h"
#include "color/image_output.h"
#include "color/working_space.h"

namespace kiln {
namespace {

const char* kCryptoLayers[2] = {"CryptoObject", "CryptoMaterial"};

bool hasCrypto(const Film& film, int type) {
    return film.layout().request().has(type == 0 ? AovKind::CryptoObject : AovKind::CryptoMaterial);
}

// A channel of the file and whether it is stored as half.
struct ExrChannel {
    std::string name;
    bool half = false;
};

// Every channel the file holds, in order, with its stored type.
std::vector<ExrChannel> exrChannels(const Film& film, const ExrOptions& options) {
    const AovRequest& request = film.layout().request();
    std::vector<ExrChannel> channels;
    auto add = [&](const std::string& name, bool half) { channels.push_back({name, half}); };
    for (const char* c : {"R", "G", "B", "A"}) add(c, options.half);
    if (options.denoised)
        for (const char* c : {"noisy.R", "noisy.G", "noisy.B"}) add(c, options.half);
    for (const DenoisedLayer& layer : film.layout().denoisedLayers())
        if (options.denoisedLayers.count(layer.name))
            for (size_t k = 0; k < 3; ++k)
                add("noisy." + film.layout().channels()[layer.channel + k].name, options.half);
    for (const AovChannel& c : film.layout().channels())
        add(c.name, (c.colour || c.name.rfind("N.", 0) == 0) && options.half);
    if (request.has(AovKind::Depth)) add("Z", false);
    if (request.has(AovKind::Samples)) add("samples.X", false);
    if (request.has(AovKind::Variance)) add("variance.V", false);
    for (int type = 0; type < 2; ++type)
        if (hasCrypto(film, type))
            for (int layer = 0; layer < kCryptoRanks / 2; ++layer)
                for (const char* c : {"R", "G", "B", "A"})
                    add(fmt::format("{}{:02d}.{}", kCryptoLayers[type], layer, c), false);
    // Exact to float: kiln denoise reads them back.
    if (film.hasHalves())
        for (int h = 0; h < 2; ++h) {
            for (const std::string& name : halfBufferChannels(h)) add(name, false);
            for (const DenoisedLayer& layer : film.layout().denoisedLayers())
                for (const std::string& name : layerHalfChannels(h, layer.name)) add(name, false);
        }
    return channels;
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

// One pixel's values in exrChannels' order.
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
ExrAttribute metadataValue(const std::string& value) {
    const char *first = value.data(), *last = value.data() + value.size();
    long long i = 0;
    if (auto [end, ec] = std::from_chars(first, last, i); ec == std::errc() && end == last) {
        if (i >= INT32_MIN && i <= INT32_MAX) return int(i);
        if (std::llabs(i) < (1ll << 53)) return double(i);
    }
    double d = 0;
    if (auto [end, ec] = std::from_chars(first, last, d);
        ec == std::errc() && end == last && std::isfinite(d))
        return d;
    return value;
}

using Header = std::map<std::string, ExrAttribute>;

void addCryptoMetadata(Header& header, const Film& film, const ExrOptions& options) {
    for (int type = 0; type < 2; ++type) {
        if (!hasCrypto(film, type)) continue;
        std::string prefix = "cryptomatte/" + cryptoLayerKey(kCryptoLayers[type]) + "/";
        header[prefix + "name"] = std::string(kCryptoLayers[type]);
        header[prefix + "hash"] = std::string("MurmurHash3_32");
        header[prefix + "conversion"] = std::string("uint32_to_float32");
        auto manifest = options.cryptoManifests.find(kCryptoLayers[type]);
        if (manifest != options.cryptoManifests.end())
            header[prefix + "manifest"] = manifest->second;
    }
}

std::vector<float> floats(const float* v, size_t n) { return std::vector<float>(v, v + n); }

}  // namespace

std::map<std::string, ExrAttribute> exrHeader(const Film& film, const Metadata& metadata,
                                              const ExrOptions& options) {
    Header header;
    header["compression"] = std::string(toString(options.compression));
    header["Software"] =
        options.software.empty() ? std::string("kiln ") + KILN_VERSION : options.software;
    header["kiln:version"] = std::string(KILN_VERSION);
    header["kiln:colorspace"] = options.colorSpace;
    // Read by OpenImageIO as the file's colour space (its own EXR writer stored none).
    header["oiio:ColorSpace"] = options.colorSpace;
    // The working space's primaries and white (Rec.709 and D65 in kiln's own config), as
    // OpenEXR's chromaticities attribute.
    header["chromaticities"] = floats(workingSpace().chromaticities.data(), 8);
    const AovRequest& request = film.layout().request();
    header["kiln:alpha"] = std::string(
        request.transparent ? "coverage by non-emitting surfaces; background transparent"
                            : "coverage by surfaces; colour premultiplied");
    if (request.has(AovKind::Depth)) {
        header["kiln:depth"] =
            std::string(request.depth == DepthMode::CameraZ ? "camera-space z (along the view axis)"
                                                            : "distance along the camera ray");
        header["kiln:depth_sample"] = std::string("nearest first hit of the pixel's samples");
        header["kiln:depth_miss"] = std::string("inf");
    }
    if (options.camera) {
        header["worldToCamera"] = floats(options.camera->worldToCamera.data(), 16);
        header["worldToNDC"] = floats(options.camera->worldToNDC.data(), 16);
    }
    addCryptoMetadata(header, film, options);
    for (const auto& [key, value] : metadata) header["kiln:" + key] = metadataValue(value);
    return header;
}

std::vector<ExrLayer> exrLayers(const Film& film) {
    std::vector<ExrLayer> layers;
    const std::vector<ExrChannel> channels = exrChannels(film, {});
    for (size_t c = 0; c < channels.size(); ++c) {
        const std::string& full = channels[c].name;
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

namespace {

Imf::Compression exrCompression(ExrCompression c) {
    switch (c) {
        case ExrCompression::None:
            return Imf::NO_COMPRESSION;
        case ExrCompression::Rle:
            return Imf::RLE_COMPRESSION;
        case ExrCompression::Zip:
            return Imf::ZIP_COMPRESSION;
        case ExrCompression::Zips:
            return Imf::ZIPS_COMPRESSION;
        case ExrCompression::Piz:
            return Imf::PIZ_COMPRESSION;
        case ExrCompression::Pxr24:
            return Imf::PXR24_COMPRESSION;
        case ExrCompression::B44:
            return Imf::B44_COMPRESSION;
        case ExrCompression::B44a:
            return Imf::B44A_COMPRESSION;
        case ExrCompression::Dwaa:
            return Imf::DWAA_COMPRESSION;
        case ExrCompression::Dwab:
            return Imf::DWAB_COMPRESSION;
    }
    return Imf::ZIP_COMPRESSION;
}

// One attribute into the OpenEXR header with the type a reader expects: the chromaticities and
// the camera matrices as OpenEXR's own types.
void insertAttribute(Imf::Header& header, const std::string& name, const ExrAttribute& value) {
    if (name == "compression") return;  // the header's compression field
    if (const int* i = std::get_if<int>(&value))
        header.insert(name, Imf::IntAttribute(*i));
    else if (const double* d = std::get_if<double>(&value))
        header.insert(name, Imf::DoubleAttribute(*d));
    else if (const std::string* s = std::get_if<std::string>(&value))
        header.insert(name, Imf::StringAttribute(*s));
    else if (const auto& v = std::get<std::vector<float>>(value);
             name == "chromaticities" && v.size() == 8)
        header.insert(name, Imf::ChromaticitiesAttribute(Imf::Chromaticities(
                                {v[0], v[1]}, {v[2], v[3]}, {v[4], v[5]}, {v[6], v[7]})));
    else if (v.size() == 16)
        header.insert(name, Imf::M44fAttribute(Imath::M44f(v[0], v[1], v[2], v[3], v[4], v[5], v[6],
                                                           v[7], v[8], v[9], v[10], v[11], v[12],
                                                           v[13], v[14], v[15])));
    else
        header.insert(name, Imf::FloatVectorAttribute(v));
}

// When the file was written, as EXR's capDate wants it ("YYYY:MM:DD HH:MM:SS", local time).
std::string captureDate() {
    std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char text[32];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &local);
    return text;
}

Imf::Header openExrHeader(const Film& film, const Header& attributes, ExrCompression compression,
                          const std::vector<ExrChannel>& channels) {
    // A render region is the data window inside the full image's display window.
    const Imath::Box2i display({0, 0}, {film.fullWidth() - 1, film.fullHeight() - 1});
    const Imath::Box2i data({film.originX(), film.originY()}, {film.originX() + film.width() - 1,
                                                               film.originY() + film.height() - 1});
    Imf::Header header(display, data);
    header.compression() = exrCompression(compression);
    for (const ExrChannel& c : channels)
        header.channels().insert(c.name, Imf::Channel(c.half ? Imf::HALF : Imf::FLOAT));
    for (const auto& [name, value] : attributes) insertAttribute(header, name, value);
    header.insert("capDate", Imf::StringAttribute(captureDate()));
    header.setType(Imf::SCANLINEIMAGE);
    return header;
}

}  // namespace

void writeExr(const std::string& path, const Film& film, const Metadata& metadata,
              const ExrOptions& options) {
    const std::vector<ExrChannel> channels = exrChannels(film, options);
    const size_t n = channels.size(), w = size_t(film.width()), h = size_t(film.height());
    // Interleaved, a 4-byte slot per value: a float, or a half channel's value rounded to half in
    // the slot's first two bytes (OpenEXR writes a channel only from a slice of its own type).
    std::vector<float> pixels(w * h * n);
    std::vector<float> px;
    const DenoisedChannels layers = denoisedChannels(film, options);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            gatherPixel(film, x, y, px, options, layers);
            float* slot = &pixels[(size_t(y) * w + size_t(x)) * n];
            for (size_t c = 0; c < n; ++c) {
                slot[c] = px[c];
                if (channels[c].half) {
                    const half value(px[c]);
                    std::memcpy(&slot[c], &value, sizeof value);
                }
            }
        }
    Imf::FrameBuffer frame;
    // OpenEXR addresses pixel (x, y) of the data window as base + x xStride + y yStride.
    const long origin = long(film.originY()) * long(w) + long(film.originX());
    char* first = reinterpret_cast<char*>(pixels.data());
    for (size_t c = 0; c < n; ++c)
        frame.insert(channels[c].name,
                     Imf::Slice(channels[c].half ? Imf::HALF : Imf::FLOAT,
                                first + (long(c) - origin * long(n)) * long(sizeof(float)),
                                n * sizeof(float), w * n * sizeof(float)));
    exrThreadsOnEveryCore();
    AtomicFile file(path);
    // OpenEXR writes through a stream kiln owns and checks: its OutputFile writes the line offsets
    // in its destructor and drops any error there, and leaves its own stream unchecked (a short
    // write would be renamed into place).
    std::ofstream os(file.tempPath(), std::ios::binary | std::ios::trunc);
    try {
        Imf::StdOFStream stream(os, file.tempPath().c_str());
        Imf::OutputFile out(stream, openExrHeader(film, exrHeader(film, metadata, options),
                                                  options.compression, channels));
        out.setFrameBuffer(frame);
        out.writePixels(film.height());
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot write EXR: " + e.what());
    }
    os.close();
    if (os.fail())
        throw std::runtime_error(path + ": cannot write EXR: a write to the disk failed");
    file.commit();
}

}  // namespace kiln
