// Exact, order-free sums of sample values: each value rounded once to a multiple of 2^-40 and
// accumulated as a 128-bit integer. Every float sample >= 2^-17 (7.6e-6) in magnitude is held
// exactly; smaller ones within 2^-41 (4.5e-13). Sums of up to 2^20 samples of magnitude
// < kMaxSampleValue cannot overflow.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace kiln {

__extension__ typedef __int128 FixedSum;

constexpr int kFixedFractionBits = 40;
constexpr double kFixedScale = 0x1p40, kFixedQuantum = 0x1p-40;
// 2^66 (7.4e19): 2^20 samples of it stay below 2^86, times 2^40 below 2^126. A luminance square
// is a value too: luminances up to 2^33 (8.6e9, the sun in absolute units) fit.
constexpr double kMaxSampleValue = 0x1p66;

// False (and out untouched) for a non-finite value or one of magnitude >= kMaxSampleValue.
// Rounds to nearest, ties to even, without a libm call on the common paths (this runs for every
// channel of every sample).
inline bool toFixed(double value, FixedSum& out) {
    double magnitude = std::fabs(value);
    if (!(magnitude < kMaxSampleValue)) return false;
    double scaled = value * kFixedScale, size = magnitude * kFixedScale;
    if (size < 0x1p51) {
        // Adding and removing 1.5 * 2^52 leaves the nearest integer (IEEE round-to-nearest-even).
        constexpr double kRound = 0x1.8p52;
        out = FixedSum(int64_t((scaled + kRound) - kRound));
    } else if (size >= 0x1p52) {
        out = size < 0x1p62 ? FixedSum(int64_t(scaled)) : FixedSum(scaled);  // already integral
    } else {
        out = FixedSum(int64_t(std::nearbyint(scaled)));
    }
    return true;
}

inline double fromFixed(FixedSum sum) { return double(sum) * kFixedQuantum; }

// The film's radiance scale: light values are held divided by 2^exponent. Outside the window
// below, the brightest emitter E is held near 2^8: samples are rounded to E * 2^-48 and kept up
// to a luminance of E * 2^25 (the luminance square's limit), room for 1/pdf factors of close
// lights. Scenes with emitters between 2^-20 and 2^20 keep exponent 0: their films hold exactly
// what an unscaled film holds (limits 2^-40 and 2^33 absolute).
inline int filmScaleExponent(double brightestEmitter) {
    constexpr int kUnscaledRange = 20, kHeldAt = 8;
    if (!(brightestEmitter > 0) || !std::isfinite(brightestEmitter)) return 0;
    int e = std::ilogb(brightestEmitter);
    return std::abs(e) > kUnscaledRange ? e - kHeldAt : 0;
}

}  // namespace kiln
