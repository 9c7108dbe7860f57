// Per-pixel accumulation with true sample counts, beauty plus the requested AOV channels; tiles own
// disjoint pixels, so no locks.
//
// The sums are exact: each sample value is rounded once to a fixed-point number (48 fraction bits,
// see fixed_sum.h) and added as an integer. Integer addition does not depend on order, so a render
// resumed from a checkpoint, refined to more samples, or split into sample-range and region shards
// and merged, holds the same bits as the render done in one go.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "renderer/core/math.h"
#include "renderer/film/aov.h"
#include "renderer/film/cryptomatte.h"
#include "renderer/film/fixed_sum.h"
#include "renderer/film/half_buffers.h"

namespace kiln {

// How a per-pixel buffer combines with the same buffer of a shard holding other samples.
enum class Accumulation : uint8_t {
    Sum = 1,          // FixedSum elements: added
    Count = 2,        // uint32 elements: added
    FirstSample = 3,  // double elements: the value of the pixel's earliest sample (ids)
    Flag = 4,         // uint8 elements: or-ed (adaptive sampling's "converged")
    Min = 5,          // float elements: the smaller (nearest depth)
    CryptoIds = 6,    // CryptoSlot elements: counts of the same id added, new ids take free slots
};

// One raw per-pixel buffer of the film: checkpoints write and read these, merges combine them, so
// a new accumulator is one more entry in Film::buffers().
struct FilmBuffer {
    std::string name;
    Accumulation rule;
    uint32_t elementBytes;
    uint32_t perPixel;  // elements per pixel
    void* data;
    size_t bytes(size_t pixels) const { return pixels * perPixel * elementBytes; }
};

// Combines a run of pixels of a shard's buffer (src, laid out as dst) into dst from pixel dstPixel
// on, by dst's rule. dstCounts: the film's sample counts before this shard (FirstSample).
void combineRun(const FilmBuffer& dst, const void* src, size_t dstPixel, size_t pixels,
                const uint32_t* dstCounts);

class Film {
  public:
    Film(int width, int height, const AovRequest& aovs = {});
    Film(Film&&) = default;
    Film& operator=(Film&&) = default;
    int width() const { return width_; }
    int height() const { return height_; }
    size_t pixelCount() const { return count_.size(); }
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
    // Light (beauty, luminance, light AOVs) is held divided by 2^exponent (fixed_sum.h,
    // filmScaleExponent). Set before the first sample; part of the checkpoint.
    void setScaleExponent(int exponent);
    int scaleExponent() const { return scaleExponent_; }

    // Non-finite samples, and samples beyond the fixed-point range (kMaxSampleValue), are counted
    // (the caller reports them) and never enter the image. sample: the sample's index, which picks
    // its half-buffer (half_buffers.h); -1: the pixel's count so far (a film filled from index 0).
    bool add(int x, int y, const SampleRecord& r, int sample = -1);
    bool add(int x, int y, const Color& c) {
        SampleRecord r;  // a sample that covered the pixel with this colour
        r.reset(layout_.request());
        r.L = c;
        r.hit = true;
        return add(x, y, r);
    }

    uint32_t samples(int x, int y) const { return count_[index(x, y)]; }
    Color pixel(int x, int y) const;
    // AOV channel c of the layout: the mean over samples (ids: the first sample's value).
    float aov(int x, int y, size_t c) const;
    // Sums of the samples' illuminance and its square (adaptive sampling, variance).
    double luminanceSum(int x, int y) const { return fromFixed(lum_[index(x, y)]) * up_; }
    double luminanceSquareSum(int x, int y) const {
        return fromFixed(lumSq_[index(x, y)]) * up_ * up_;
    }
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
    // With the DenoiseHalves request: half h's kHalfChannels values (half_buffers.h; colour in
    // scene light) and how many samples it holds.
    bool hasHalves() const { return !halves_.empty(); }
    void halfMean(int x, int y, int h, float out[kHalfChannels]) const;
    // With halves, each denoised light-path layer's too (layout().denoisedLayers()[layer]): half
    // h's colour and the variance of each mean (in scene light), over halfSamples(x, y, h).
    void layerHalfMean(int x, int y, int h, size_t layer, float out[kLayerHalfChannels]) const;
    uint32_t halfSamples(int x, int y, int h) const {
        return halfCount_[2 * index(x, y) + size_t(h)];
    }
    // Adaptive sampling: the pixel met the confidence test and takes no more samples.
    bool converged(int x, int y) const { return converged_[index(x, y)] != 0; }
    void setConverged(int x, int y) { converged_[index(x, y)] = 1; }

    // The whole per-pixel state, in a fixed order (the checkpoint's order).
    std::vector<FilmBuffer> buffers();
    // The same list for reading (checkpoint writes); its pointers must not be written through.
    std::vector<FilmBuffer> buffers() const { return const_cast<Film*>(this)->buffers(); }
    // Where a shard's pixel (0, 0) lands in this film (its index); throws std::invalid_argument if
    // the shard's region does not lie inside this one.
    size_t placeShard(int originX, int originY, int shardWidth, int shardHeight, int fullWidth,
                      int fullHeight) const;
    const uint32_t* sampleCounts() const { return count_.data(); }

  private:
    size_t index(int x, int y) const { return size_t(y) * size_t(width_) + size_t(x); }
    int width_, height_;
    int originX_ = 0, originY_ = 0, fullWidth_ = 0, fullHeight_ = 0;
    int scaleExponent_ = 0;
    double down_ = 1.0, up_ = 1.0;  // 2^-exponent into the sums, 2^exponent out of them
    AovLayout layout_;
    std::vector<size_t> slot_;   // per layout channel: its index in aovSum_ or aovFirst_
    std::vector<FixedSum> sum_;  // beauty RGB, 3 per pixel
    std::vector<FixedSum> lum_, lumSq_;
    std::vector<uint32_t> count_;
    std::vector<FixedSum> aovSum_;  // the averaged channels per pixel, in layout order
    std::vector<double> aovFirst_;  // the first-sample channels per pixel, in layout order
    std::vector<uint8_t> converged_;
    std::vector<uint32_t> covered_;      // samples that covered the pixel (alpha)
    std::vector<float> depth_;           // nearest first-hit Z (with the Depth AOV)
    std::vector<CryptoSlot> crypto_[2];  // kCryptoSlots per pixel: objects, materials
    // 2 halves per pixel (DenoiseHalves), each kHalfSums and then kLayerHalfSums per denoised
    // layer: halfStride_ sums.
    std::vector<FixedSum> halves_;
    size_t halfStride_ = kHalfSums;
    std::vector<uint32_t> halfCount_;  // 2 per pixel: the samples of each half
    size_t sumChannels_ = 0, firstChannels_ = 0;
    void addCrypto(size_t i, int type, uint32_t id);
    void addToHalf(size_t i, int half, const FixedSum colour[3], const Color& scaled,
                   const SampleRecord& r);
    void addLayersToHalf(FixedSum* sums, const FixedSum* fixed, const double* values) const;
};

}  // namespace kiln
