// Counter-based random numbers: every value is a pure function of (seed, pixel, sample index,
// dimension), so an image is bit-identical whatever the thread count or tile order.
#pragma once

#include <cstdint>

namespace kiln {

// SplitMix64 finaliser: a strong 64-bit mixer.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class Sampler {
  public:
    Sampler(uint64_t seed, uint64_t pixelIndex, uint64_t sampleIndex)
        : key_(mix64(mix64(mix64(seed) ^ pixelIndex) ^ sampleIndex)) {}
    float next1D() {
        uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ull * ++dimension_);
        return float(bits >> 40) * 0x1.0p-24f;  // [0, 1)
    }
    uint32_t dimension() const { return dimension_; }

  private:
    uint64_t key_;
    uint32_t dimension_ = 0;
};

}  // namespace kiln
