// The image module's writers (OpenImageIO): the heat map, a preview in another format than PNG, and
// every image written through OIIO (writeAtomically, oiio_write.h).
#include "color/image_output.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/fmath.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "color/atomic_file.h"
#include "color/exr_colour_space.h"
#include "color/oiio_write.h"

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

// The OpenImageIO writer for a file name's extension (png, jpeg, ...).
std::string formatOf(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    return ext.empty() ? "png" : ext.substr(1);
}

}  // namespace

void writeDisplayImage(const std::string& path, int w, int h, const std::vector<uint8_t>& rgba) {
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 3;
    OIIO::ImageBuf buf(spec, const_cast<uint8_t*>(rgba.data()));
    writeAtomically(path, formatOf(path), spec, buf, "preview");
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

}  // namespace kiln
