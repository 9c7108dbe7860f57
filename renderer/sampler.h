// Counter-based random numbers: every value is a pure function of (seed, pixel, sample index,
// dimension), so an image is bit-identical whatever the thread count or tile order.
#pragma once

#include <algorithm>
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
    float next1D() { return float(nextBits() >> 40) * 0x1.0p-24f; }  // [0, 1)
    // 64 random bits for the next dimension.
    uint64_t nextBits() { return mix64(key_ + 0x9e3779b97f4a7c15ull * ++dimension_); }
    uint32_t dimension() const { return dimension_; }

  private:
    uint64_t key_;
    uint32_t dimension_ = 0;
};

// Kensler's hashed permutation of [0, n) ("Correlated Multi-Jittered Sampling", Pixar 2013): a
// bijection picked by `seed`, computed without storage by cycle-walking within a power-of-two mask.
constexpr uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t seed) {
    uint32_t w = n - 1;
    w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
    do {
        i ^= seed, i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & w) >> 4;
        i ^= seed >> 8, i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & w) >> 1, i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11, i *= 0x74dcb303u;
        i ^= (i & w) >> 2, i *= 0x9e501cc3u;
        i ^= (i & w) >> 2, i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    return (i + seed) % n;
}

// n points in [0,1)^3 whose every coordinate falls once in each of n equal strata (a Latin
// hypercube): the -l light samples of one vertex then spread over the light instead of clumping.
// Averaging f over the set is unbiased: each point is uniform within its stratum.
class LatinHypercube3 {
  public:
    LatinHypercube3(uint32_t n, Sampler& sampler)
        : n_(n),
          seedY_(uint32_t(sampler.nextBits() >> 32)),
          seedZ_(uint32_t(sampler.nextBits() >> 32)) {}
    // Point k of the set from three fresh uniform numbers (its jitter within the strata).
    void point(uint32_t k, float jx, float jy, float jz, float& x, float& y, float& z) const {
        x = stratum(k, jx);
        y = stratum(permuteIndex(k, n_, seedY_), jy);
        z = stratum(permuteIndex(k, n_, seedZ_), jz);
    }

  private:
    float stratum(uint32_t s, float j) const {
        return std::min((float(s) + j) / float(n_), 0x1.fffffep-1f);  // rounding must not reach 1
    }
    uint32_t n_, seedY_, seedZ_;
};

}  // namespace kiln
