// Per-pixel accumulation with true sample counts, beauty plus the requested AOV channels; tiles own
// disjoint pixels, so no locks.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "renderer/core/math.h"
#include "renderer/film/aov.h"
#include "renderer/film/cryptomatte.h"

namespace kiln {

class Film {
  public:
    Film(int width, int height, const AovRequest& aovs = {});
    int width() const { return width_; }
    int height() const { return height_; }
    // A film that holds a region of a larger image: where its pixel (0, 0) sits in that image (the
    // EXR's data window inside its display window).
    void setRegion(int originX, int originY, int fullWidth, int fullHeight) {
        originX_ = originX, originY_ = originY, fullWidth_ = fullWidth, fullHeight_ = fullHeight;
    }
    int originX() const { return originX_; }
    int originY() const { return originY_; }
    int fullWidth() const { return fullWidth_ > 0 ? fullWidth_ : width_; }
    int fullHeight() const { return fullHeight_ > 0 ? fullHeight_ : height_; }
    const AovLayout& layout() const { return layout_; }

    // Non-finite samples are counted (the caller reports them) and never enter the image.
    bool add(int x, int y, const SampleRecord& r);
    bool add(int x, int y, const Color& c) {
        SampleRecord r;  // a sample that covered the pixel with this colour
        r.reset(layout_.request());
        r.L = c;
        r.hit = true;
        return add(x, y, r);
    }

    uint32_t samples(int x, int y) const { return count_[index(x, y)]; }
    Color pixel(int x, int y) const {
        size_t i = index(x, y);
        return count_[i] ? Color(sum_[i] / double(count_[i])) : Color(0.0f);
    }
    // AOV channel c of the layout: the mean over samples (ids: the first sample's value).
    float aov(int x, int y, size_t c) const;
    // Sums of the samples' illuminance and its square (adaptive sampling, variance).
    double luminanceSum(int x, int y) const { return lum_[index(x, y)]; }
    double luminanceSquareSum(int x, int y) const { return lumSq_[index(x, y)]; }
    // Estimator variance of the pixel's luminance mean: sample variance / n.
    double luminanceVariance(int x, int y) const;
    uint64_t totalSamples() const;
    // Coverage: the fraction of the pixel's samples whose camera ray hit a surface (with
    // transparent, a surface that does not emit). The beauty and light AOVs are premultiplied by
    // it.
    float alpha(int x, int y) const;
    // The nearest first hit's Z over the pixel's samples (one sample's, never a mean); +inf where
    // none hit. Only with the Depth AOV.
    float depth(int x, int y) const { return depth_[index(x, y)]; }
    // Cryptomatte type 0 (objects) or 1 (materials): (id, coverage) pairs ranked by coverage, empty
    // ranks (0, 0).
    using CryptoRanks = std::array<std::pair<float, float>, kCryptoRanks>;
    CryptoRanks cryptoRanks(int x, int y, int type) const;

  private:
    size_t index(int x, int y) const { return size_t(y) * size_t(width_) + size_t(x); }
    int width_, height_;
    int originX_ = 0, originY_ = 0, fullWidth_ = 0, fullHeight_ = 0;
    AovLayout layout_;
    std::vector<Vec3d> sum_;
    std::vector<double> lum_, lumSq_;
    std::vector<uint32_t> count_;
    std::vector<double> aov_;            // channels per pixel, in layout order
    std::vector<uint32_t> covered_;      // samples that covered the pixel (alpha)
    std::vector<float> depth_;           // nearest first-hit Z (with the Depth AOV)
    std::vector<CryptoSlot> crypto_[2];  // kCryptoSlots per pixel: objects, materials
    void addCrypto(size_t i, int type, uint32_t id);
};

}  // namespace kiln
