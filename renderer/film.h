// Per-pixel accumulation with true sample counts; tiles own disjoint pixels, so no locks.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/math.h"

namespace kiln {

class Film {
public:
    Film(int width, int height)
        : width_(width), height_(height), sum_(size_t(width) * height), lum_(sum_.size()), lumSq_(sum_.size()),
          count_(sum_.size()) {}
    int width() const { return width_; }
    int height() const { return height_; }
    // Non-finite samples are counted (the caller reports them) and never enter the image.
    bool add(int x, int y, const Color& c) {
        size_t i = size_t(y) * width_ + x;
        ++count_[i];
        if (!isFinite(c)) return false;
        sum_[i] += Vec3d(c);
        double illum = luminance(c);
        lum_[i] += illum;
        lumSq_[i] += illum * illum;
        return true;
    }
    // Sums of the samples' illuminance and its square (adaptive sampling, variance).
    double luminanceSum(int x, int y) const { return lum_[size_t(y) * width_ + x]; }
    double luminanceSquareSum(int x, int y) const { return lumSq_[size_t(y) * width_ + x]; }
    uint32_t samples(int x, int y) const { return count_[size_t(y) * width_ + x]; }
    Color pixel(int x, int y) const {
        size_t i = size_t(y) * width_ + x;
        return count_[i] ? Color(sum_[i] / double(count_[i])) : Color(0.0f);
    }
    uint64_t totalSamples() const {
        uint64_t n = 0;
        for (uint32_t c : count_) n += c;
        return n;
    }

private:
    int width_, height_;
    std::vector<Vec3d> sum_;
    std::vector<double> lum_, lumSq_;
    std::vector<uint32_t> count_;
};

}  // namespace kiln
