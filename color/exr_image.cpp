// ExrImage's reading and writing (exr_image.h), in the image module: the OpenImageIO side.
#include "color/exr_image.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include "color/oiio_write.h"

namespace kiln {

void readExrImage(const std::string& path, ExrImage& image) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageReadError(path, "cannot read: " + OIIO::geterror());
    image.spec_ = std::make_shared<OIIO::ImageSpec>(in->spec());
    const OIIO::ImageSpec& spec = *image.spec_;
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw ImageReadError(path, "holds no pixels");
    image.width_ = spec.width, image.height_ = spec.height;
    image.names_ = spec.channelnames;
    image.names_.resize(size_t(spec.nchannels));
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        image.attributes_[p.name().string()] = p.get_string();
    image.values_.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values_.data()))
        throw ImageReadError(path, "cannot read its pixels: " + in->geterror());
}

void writeExrImage(const std::string& path, const ExrImage& image) {
    OIIO::ImageSpec spec = *image.spec_;
    if (spec.channelformats.empty())
        spec.channelformats.assign(size_t(spec.nchannels), spec.format);
    for (const auto& [name, half] : image.added_) {
        spec.channelnames.push_back(name);
        spec.channelformats.push_back(half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
        ++spec.nchannels;
    }
    for (const auto& [name, value] : image.setAttributes_) spec.attribute(name, value);
    OIIO::ImageSpec memSpec = spec;
    memSpec.channelformats.clear();
    memSpec.set_format(OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(memSpec, const_cast<float*>(image.values_.data()));
    writeAtomically(path, "openexr", spec, buf, "EXR");
}

}  // namespace kiln
