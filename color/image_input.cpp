#include "color/image_input.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kiln {
namespace {

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageReadError(path, "cannot read image: " + OIIO::geterror());
    return in;
}

}  // namespace

bool isSrgbEncoded(const OIIO::ImageSpec& spec) {
    return spec.format.basetype == OIIO::TypeDesc::UINT8 ||
           OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
}

TexelConversion colourConversion(const OIIO::ImageSpec& spec) {
    const OIIO::ParamValue* chroma =
        spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
    Chromaticities stated;
    if (chroma)
        for (int i = 0; i < 8; ++i)
            stated[size_t(i)] = static_cast<const float*>(chroma->data())[i];
    return imageConversion(isSrgbEncoded(spec), chroma ? &stated : nullptr);
}

ImageHeader readImageHeader(const std::string& path) {
    auto in = openImage(path);
    const OIIO::ImageSpec& spec = in->spec();
    return {spec.width, spec.height, spec.nchannels};
}

RgbImage readWorkingSpaceImage(const std::string& path) {
    auto in = openImage(path);
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels < 3)
        throw ImageReadError(path, "needs RGB channels, has " + std::to_string(spec.nchannels));
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw ImageReadError(path, "cannot read image: " + in->geterror());
    colourConversion(spec).apply(data.data(), size_t(spec.width) * spec.height, spec.nchannels);
    RgbImage image;
    image.width = spec.width, image.height = spec.height;
    image.pixels.resize(size_t(spec.width) * spec.height);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const float* p = &data[i * size_t(spec.nchannels)];
        image.pixels[i] = Color(p[0], p[1], p[2]);
    }
    return image;
}

bool readChannelImage(const std::string& path, ChannelImage& image) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return false;
    const OIIO::ImageSpec& spec = in->spec();
    image.width = spec.width, image.height = spec.height;
    image.channelNames.assign(spec.channelnames.begin(), spec.channelnames.end());
    image.values.resize(size_t(spec.width) * spec.height * spec.nchannels);
    return in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values.data());
}

}  // namespace kiln
