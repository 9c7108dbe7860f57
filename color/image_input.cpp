#include "color/image_input.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "color/chromaticities.h"
#include "color/working_space.h"

namespace kiln {
namespace {

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageReadError(path, "cannot read image: " + OIIO::geterror());
    return in;
}

Mat3 toWorkingMatrix(const OIIO::ImageSpec& spec) {
    Mat3 identity = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    const OIIO::ParamValue* chroma =
        spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
    if (!chroma) return identity;
    Chromaticities c;
    for (int i = 0; i < 8; ++i) c[size_t(i)] = static_cast<const float*>(chroma->data())[i];
    return sameChromaticities(c, kRec709D65) ? identity : toWorkingSpace(c);
}

}  // namespace

bool isSrgbEncoded(const OIIO::ImageSpec& spec) {
    return spec.format.basetype == OIIO::TypeDesc::UINT8 ||
           OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
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
    bool srgbEncoded = isSrgbEncoded(spec);
    // sRGB-encoded texels are decoded straight into scene_linear by OCIO; linear ones are in
    // their stated chromaticities (else Rec.709), taken to Rec.709, then to the working space.
    Mat3 toWorking = toWorkingMatrix(spec);
    const WorkingSpace& space = workingSpace();
    if (!srgbEncoded && !space.rec709) toWorking = multiply(space.fromRec709, toWorking);
    RgbImage image;
    image.width = spec.width, image.height = spec.height;
    image.pixels.resize(size_t(spec.width) * spec.height);
    if (srgbEncoded) decodeSrgbTexels(data.data(), image.pixels.size(), spec.nchannels);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const float* p = &data[i * size_t(spec.nchannels)];
        image.pixels[i] = applyMatrix(toWorking, Color(p[0], p[1], p[2]));
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
