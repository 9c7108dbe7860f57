// An EXR read whole (every channel as float, its header kept), changed and written again, for
// commands that rework a finished file (kiln denoise). Reading and writing are the image module's
// (image_module.h); the rest is plain data, so the kiln executable never calls OpenImageIO itself.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "color/image_input.h"

namespace kiln {

class ExrImage;

// The module's two calls. readExrImage throws ImageReadError ("FILE: REASON"); writeExrImage
// writes through an AtomicFile and throws std::runtime_error naming path.
void readExrImage(const std::string& path, ExrImage& image);
void writeExrImage(const std::string& path, const ExrImage& image);

class ExrImage {
  public:
    static ExrImage read(const std::string& path) {
        ExrImage image;
        readExrImage(path, image);
        return image;
    }
    int width() const { return width_; }  // of the data window
    int height() const { return height_; }
    int channels() const { return int(names_.size()); }
    int channel(const std::string& name) const;  // -1 when absent
    // Channel c at pixel (x, y) of the data window.
    float value(int x, int y, int c) const {
        return values_[(size_t(y) * size_t(width()) + size_t(x)) * size_t(channels()) + size_t(c)];
    }
    // A header attribute as text; "" when absent.
    std::string attribute(const std::string& name) const;
    // Channel name set to values (width * height, row-major), appended when absent; half: stored
    // as half floats.
    void setChannel(const std::string& name, const std::vector<float>& values, bool half);
    void setAttribute(const std::string& name, const std::string& value);
    void write(const std::string& path) const { writeExrImage(path, *this); }

  private:
    friend void readExrImage(const std::string& path, ExrImage& image);
    friend void writeExrImage(const std::string& path, const ExrImage& image);

    std::shared_ptr<OIIO::ImageSpec> spec_;  // the header as read (the module's type)
    int width_ = 0, height_ = 0;
    std::vector<std::string> names_;                   // every channel, in the file's order
    std::vector<std::pair<std::string, bool>> added_;  // channels set beyond the file's: half?
    std::map<std::string, std::string> attributes_;    // the header's, as text
    std::vector<std::pair<std::string, std::string>> setAttributes_;
    std::vector<float> values_;  // interleaved, every channel
};

}  // namespace kiln
