// Counter-based sample values: every value is a pure function of (seed, pixel, sample index,
// dimension), so an image is bit-identical whatever the thread count, tile order, shard split or
// resume point.
#pragma once

#include <cstdint>

#include "renderer/core/enum_names.h"
#include "renderer/core/sobol.h"

namespace kiln {

// SplitMix64 finaliser: a strong 64-bit mixer.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// independent: uniform random numbers. sobol: consecutive dimensions in pairs of shuffled,
// Owen-scrambled Sobol points (sobol.h), stratified over a pixel's samples.
enum class SamplerKind : uint8_t { Independent, Sobol };
template <>
struct EnumNames<SamplerKind> {
    static constexpr std::pair<SamplerKind, const char*> table[] = {
        {SamplerKind::Independent, "independent"}, {SamplerKind::Sobol, "sobol"}};
};

class Sampler {
  public:
    // What every sample of one pixel starts from: (seed, pixel) mixed, found once for all of a
    // pixel's samples (the camera's loop) instead of once per sample.
    struct PixelKey {
        uint64_t key;
    };
    static PixelKey pixelKey(uint64_t seed, uint64_t pixelIndex) {
        return {mix64(mix64(seed) ^ pixelIndex)};
    }
    Sampler(uint64_t seed, uint64_t pixelIndex, uint64_t sampleIndex,
            SamplerKind kind = SamplerKind::Independent)
        : Sampler(pixelKey(seed, pixelIndex), sampleIndex, kind) {}
    Sampler(PixelKey pixel, uint64_t sampleIndex, SamplerKind kind)
        : key_(pixel.key), reversedSample_(reverseBits32(uint32_t(sampleIndex))), kind_(kind) {
        if (kind_ == SamplerKind::Independent) key_ = mix64(key_ ^ sampleIndex);
    }
    float next1D() {
        uint32_t d = ++dimension_;
        if (kind_ == SamplerKind::Independent) {
            uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ull * d);
            return float(bits >> 40) * 0x1.0p-24f;  // [0, 1)
        }
        // Dimensions 1, 2 form pair 0; 3, 4 pair 1; ... The pair's second value is kept for
        // the next call (computed then if the first was skipped).
        if (d % 2 == 0 && pendingValid_) return toUnit(pendingY_);
        SobolPair p = shuffledScrambledSobol2D(reversedSample_, pairSeed((d - 1) / 2));
        pendingY_ = p.y;
        pendingValid_ = true;
        return toUnit(d % 2 == 0 ? p.y : p.x);
    }
    // Consumes a dimension without computing it: a value the caller would not use (the one light's
    // choice, a pinhole's lens position). Every later value is what it would have been.
    void skip1D() {
        if (++dimension_ % 2 == 1) pendingValid_ = false;
    }
    void skip2D() {
        if (kind_ == SamplerKind::Sobol && dimension_ % 2 == 1) ++dimension_;
        skip1D();
        skip1D();
    }
    // The two coordinates of one 2D sample (a light's or a BSDF's square). sobol: both from one
    // pair, so the points are stratified in 2D (a pair's leftover value is skipped); independent:
    // two next1D values, as before.
    struct Point2 {
        float u, v;
    };
    Point2 next2D() {
        if (kind_ == SamplerKind::Sobol && dimension_ % 2 == 1) ++dimension_;
        float u = next1D();
        return {u, next1D()};
    }
    // The 2D sample of a path's bounce direction. sobol: the bounces of vertices 1 and 2 of a path
    // (3 and 4, ...) are the two halves of one 4D Sobol point, dimensions 0-1 and 2-3 at one
    // shuffled index, so a pixel's samples stratify their directions jointly (the two-bounce
    // paths of an interior: 9 % less error at equal samples, docs/performance.md); independent:
    // next2D. Each half takes the next pair, as next2D would.
    Point2 nextBounce2D() {
        if (kind_ != SamplerKind::Sobol) return next2D();
        const uint32_t seed = pairSeed(takePairs(1));
        if (!bounceHalfOpen_)
            bounceIndex_ = shuffledSobolIndex(reversedSample_, seed ^ 0x5bd1e995u);
        SobolPair p = scrambledSobol4DHalf(bounceIndex_, seed, bounceHalfOpen_);
        bounceHalfOpen_ = !bounceHalfOpen_;
        return {toUnit(p.x), toUnit(p.y)};
    }
    // Splitting: `count` draws at one vertex (its light samples) from the same `pairs` pairs, draw
    // k of sample i at Sobol index i * count + k (Keller's trajectory splitting by dependent
    // sampling; Cycles' path_branched_rng_2D). A vertex's draws are then one aligned block of
    // each pair's sequence, stratified among themselves (a (0,m,2)-net for count = 2^m), and a
    // pixel's draws at its first vertex one sequence of count times its samples; independent
    // draws stay independent. Reserves the pairs (after next2D's alignment).
    struct Split {
        uint32_t pair = 0, count = 1;
    };
    Split split(uint32_t pairs, uint32_t count) { return {takePairs(pairs), count}; }
    // Draw k of the split's pair pairOffset.
    Point2 splitDraw(Split s, uint32_t pairOffset, uint32_t k) const {
        const uint32_t pair = s.pair + pairOffset;
        if (kind_ == SamplerKind::Independent) {
            uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ull * (2 * uint64_t(pair) + 1) +
                                  0xd1b54a32d192ed03ull * k);
            return {float(bits >> 40) * 0x1.0p-24f, float(bits & 0xffffffu) * 0x1.0p-24f};
        }
        // The sample's index times count plus k (modulo 2^32, as the index itself).
        const uint32_t index = reverseBits32(reversedSample_) * s.count + k;
        SobolPair p = shuffledScrambledSobol2D(reverseBits32(index), pairSeed(pair));
        return {toUnit(p.x), toUnit(p.y)};
    }
    uint32_t dimension() const { return dimension_; }
    SamplerKind kind() const { return kind_; }

  private:
    // Reserves the next `pairs` whole pairs (after an odd dimension's leftover) for draws that do
    // not go through next1D; returns the first.
    uint32_t takePairs(uint32_t pairs) {
        if (dimension_ % 2 == 1) ++dimension_;
        const uint32_t first = dimension_ / 2;
        dimension_ += 2 * pairs;
        pendingValid_ = false;
        return first;
    }
    // 24 bits, as the independent sampler, so a value is never rounded up to 1.
    static float toUnit(uint32_t fixed) { return float(fixed >> 8) * 0x1.0p-24f; }
    uint32_t pairSeed(uint32_t pair) const {
        return uint32_t(mix64(key_ + 0x9e3779b97f4a7c15ull * (uint64_t(pair) + 1)));
    }
    uint64_t key_;
    uint32_t reversedSample_;  // the Sobol index, bit-reversed (independent: mixed into key_)
    uint32_t dimension_ = 0;
    uint32_t pendingY_ = 0;
    bool pendingValid_ = false;
    bool bounceHalfOpen_ = false;  // nextBounce2D drew a 4D point's first half, not its second
    uint32_t bounceIndex_ = 0;     // that point's shuffled index (shuffledSobolIndex)
    SamplerKind kind_;
};

}  // namespace kiln
