#include "color/exr_image.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include "color/oiio_write.h"

namespace kiln {

ExrImage ExrImage::read(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageReadError(path, "cannot read: " + OIIO::geterror());
    ExrImage image;
    image.spec_ = std::make_shared<OIIO::ImageSpec>(in->spec());
    const OIIO::ImageSpec& spec = *image.spec_;
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw ImageReadError(path, "holds no pixels");
    image.values_.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values_.data()))
        throw ImageReadError(path, "cannot read its pixels: " + in->geterror());
    return image;
}

int ExrImage::width() const { return spec_->width; }
int ExrImage::height() const { return spec_->height; }
int ExrImage::channels() const { return spec_->nchannels; }

int ExrImage::channel(const std::string& name) const { return spec_->channelindex(name); }

std::string ExrImage::attribute(const std::string& name) const {
    const OIIO::ParamValue* p = spec_->find_attribute(name);
    return p ? p->get_string() : std::string();
}

void ExrImage::setChannel(const std::string& name, const std::vector<float>& values, bool half) {
    OIIO::ImageSpec& spec = *spec_;
    const size_t pixels = size_t(spec.width) * size_t(spec.height);
    int c = channel(name);
    if (c < 0) {
        const size_t old = size_t(spec.nchannels);
        std::vector<float> wider(pixels * (old + 1));
        for (size_t p = 0; p < pixels; ++p)
            std::copy_n(&values_[p * old], old, &wider[p * (old + 1)]);
        values_.swap(wider);
        if (spec.channelformats.empty()) spec.channelformats.assign(old, spec.format);
        spec.channelnames.push_back(name);
        spec.channelformats.push_back(half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
        c = spec.nchannels++;
    }
    const size_t n = size_t(spec.nchannels);
    for (size_t p = 0; p < pixels; ++p) values_[p * n + size_t(c)] = values[p];
}

void ExrImage::setAttribute(const std::string& name, const std::string& value) {
    spec_->attribute(name, value);
}

void ExrImage::write(const std::string& path) const {
    OIIO::ImageSpec memSpec = *spec_;
    memSpec.channelformats.clear();
    memSpec.set_format(OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(memSpec, const_cast<float*>(values_.data()));
    writeAtomically(path, "openexr", *spec_, buf, "EXR");
}

}  // namespace kiln
