// Exact, order-free sums of sample values: each value rounded once to a multiple of 2^-48 and
// accumulated as a 128-bit integer. Every float sample >= 2^-25 (3e-8) in magnitude is held
// exactly; smaller ones within 2^-49. Sums of up to 2^20 samples of magnitude < kMaxSampleValue
// cannot overflow.
#pragma once

#include <cmath>
#include <cstdint>

namespace kiln {

__extension__ typedef __int128 FixedSum;

constexpr int kFixedFractionBits = 48;
// 2^58: 2^20 samples of it stay below 2^78, times 2^48 below 2^126.
constexpr double kMaxSampleValue = 0x1p58;

// False (and out untouched) for a non-finite value or one of magnitude >= kMaxSampleValue.
inline bool toFixed(double value, FixedSum& out) {
    if (!(std::fabs(value) < kMaxSampleValue)) return false;
    double scaled = std::nearbyint(value * 0x1p48);
    out = std::fabs(scaled) < 0x1p62 ? FixedSum(int64_t(scaled)) : FixedSum(scaled);
    return true;
}

inline double fromFixed(FixedSum sum) { return double(sum) * 0x1p-48; }

}  // namespace kiln
