// An EXR read whole (every channel as float, its header kept), changed and written again, for
// commands that rework a finished file (kiln denoise).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "color/image_input.h"

namespace kiln {

class ExrImage {
  public:
    // Throws ImageReadError ("FILE: REASON") when the file cannot be read as an image.
    static ExrImage read(const std::string& path);
    int width() const;  // of the data window
    int height() const;
    int channels() const;
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
    // Written through an AtomicFile. Throws std::runtime_error naming path.
    void write(const std::string& path) const;

  private:
    std::shared_ptr<OIIO::ImageSpec> spec_;
    std::vector<float> values_;  // interleaved, every channel
};

}  // namespace kiln
