#include "color/exr_rgb_input.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <strings.h>

#include <cstdint>
#include <exception>
#include <vector>

#include "color/exr_threads.h"
#include "renderer/core/memory.h"

namespace kiln {
namespace {

// Names OpenImageIO sorts, case-insensitively, among the first three of a layer (R, Red, G,
// Green, B): with one of these beside R, G and B its first three would not be R, G, B.
bool sortsAmongRgb(const char* name) {
    for (const char* early : {"R", "Red", "G", "Green", "B"})
        if (strcasecmp(name, early) == 0) return true;
    return false;
}

// R, G and B unlayered, half or float, nothing OpenImageIO would put before them (it sorts the
// unlayered channels first, R, G, B at their head), and no channel subsampled (OpenImageIO
// refuses the file).
bool plainRgb(const Imf::ChannelList& channels) {
    int found = 0;
    for (auto c = channels.begin(); c != channels.end(); ++c) {
        const Imf::Channel& ch = c.channel();
        if (ch.xSampling != 1 || ch.ySampling != 1) return false;
        const std::string name = c.name();
        if (name.find('.') != std::string::npos) continue;  // a layer: sorted after these
        const bool rgb = name == "R" || name == "G" || name == "B";
        if (!rgb && sortsAmongRgb(name.c_str())) return false;
        if (!rgb) continue;
        if (ch.type == Imf::UINT) return false;  // OpenImageIO converts integers its own way
        ++found;
    }
    return found == 3;
}

// OpenImageIO keeps attribute names regardless of case (the last of a name wins) and takes a
// chromaticities of another type or spelling too: the colour is read here only where the two
// attributes it acts on are spelt and typed as OpenEXR writes them, or absent.
bool plainColourAttributes(const Imf::Header& header) {
    for (auto a = header.begin(); a != header.end(); ++a) {
        const std::string type = a.attribute().typeName();
        if (strcasecmp(a.name(), "oiio:ColorSpace") == 0 &&
            (std::string(a.name()) != "oiio:ColorSpace" || type != "string"))
            return false;
        if (strcasecmp(a.name(), "chromaticities") == 0 &&
            (std::string(a.name()) != "chromaticities" || type != "chromaticities"))
            return false;
    }
    return true;
}

// OpenImageIO's isSrgbEncoded for an EXR: only a stated oiio:ColorSpace "sRGB".
bool statesSrgb(const Imf::Header& header) {
    const auto* space = header.findTypedAttribute<Imf::StringAttribute>("oiio:ColorSpace");
    return space && strcasecmp(space->value().c_str(), "sRGB") == 0;
}

TexelConversion conversionOf(const Imf::Header& header) {
    const auto* attribute =
        header.findTypedAttribute<Imf::ChromaticitiesAttribute>("chromaticities");
    Chromaticities stated{};
    if (attribute) {
        const Imf::Chromaticities& c = attribute->value();
        stated = {c.red.x, c.red.y, c.green.x, c.green.y, c.blue.x, c.blue.y, c.white.x, c.white.y};
    }
    return imageConversion(statesSrgb(header), attribute ? &stated : nullptr);
}

std::optional<RgbImage> readPlainRgb(const std::string& path) {
    bool tiled = false, deep = false, multiPart = false;
    if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multiPart) || deep) return std::nullopt;
    exrThreadsOnEveryCore();
    Imf::InputFile file(path.c_str(), Imf::globalThreadCount());
    const Imf::Header& header = file.header();
    if (!plainRgb(header.channels()) || !plainColourAttributes(header)) return std::nullopt;
    const Imath::Box2i window = header.dataWindow();
    const int64_t w = int64_t(window.max.x) - window.min.x + 1,
                  h = int64_t(window.max.y) - window.min.y + 1;
    // Sizes an int holds, and room for the floats and the image made from them.
    if (w < 1 || h < 1 || w > (1 << 20) || h > (1 << 20) ||
        uint64_t(w * h) * 2 * sizeof(Color) > availableMemoryBytes())
        return std::nullopt;
    std::vector<float> rgb(size_t(w * h) * 3);
    Imf::FrameBuffer frame;
    const char* names[] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
        frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, window,
                                                3 * sizeof(float), size_t(w) * 3 * sizeof(float)));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    conversionOf(header).apply(rgb.data(), size_t(w * h), 3);
    RgbImage image;
    image.width = int(w), image.height = int(h);
    image.pixels.resize(size_t(w * h));
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = Color(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    return image;
}

}  // namespace

std::optional<RgbImage> readExrRgb(const std::string& path) {
    try {
        return readPlainRgb(path);
    } catch (const std::exception&) {  // OpenEXR's errors: the module reads it and says why
        return std::nullopt;
    }
}

}  // namespace kiln
