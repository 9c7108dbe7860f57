// ExrImage's plain-data side (exr_image.h), in the executable: no OpenImageIO here.
#include <algorithm>

#include "color/exr_image.h"

namespace kiln {

int ExrImage::channel(const std::string& name) const {
    auto it = std::find(names_.begin(), names_.end(), name);
    return it == names_.end() ? -1 : int(it - names_.begin());
}

std::string ExrImage::attribute(const std::string& name) const {
    for (auto it = setAttributes_.rbegin(); it != setAttributes_.rend(); ++it)
        if (it->first == name) return it->second;
    auto found = attributes_.find(name);
    return found == attributes_.end() ? std::string() : found->second;
}

void ExrImage::setChannel(const std::string& name, const std::vector<float>& values, bool half) {
    const size_t pixels = size_t(width_) * size_t(height_);
    int c = channel(name);
    if (c < 0) {
        const size_t old = names_.size();
        std::vector<float> wider(pixels * (old + 1));
        for (size_t p = 0; p < pixels; ++p)
            std::copy_n(&values_[p * old], old, &wider[p * (old + 1)]);
        values_.swap(wider);
        names_.push_back(name);
        added_.push_back({name, half});
        c = int(old);
    }
    const size_t n = names_.size();
    for (size_t p = 0; p < pixels; ++p) values_[p * n + size_t(c)] = values[p];
}

void ExrImage::setAttribute(const std::string& name, const std::string& value) {
    setAttributes_.push_back({name, value});
}

}  // namespace kiln
