// Shuffled, Owen-scrambled Sobol points after Burley, "Practical Hash-based Owen Scrambling" (JCGT
// 2020): dimensions come in pairs, each pair the first two Sobol dimensions (a (0,2)-sequence) at
// an index shuffled by a nested uniform scramble, each coordinate Owen-scrambled by a hash. Every
// power-of-two prefix of a pixel's samples is a (0,m,2)-net in each pair; pairs are decorrelated by
// their seeds. No tables: only the first two Sobol generator matrices.
#pragma once

#include <cstdint>

namespace kiln {

// A byte swap (one instruction) leaves three swap steps instead of five.
constexpr uint32_t reverseBits32(uint32_t x) {
    x = __builtin_bswap32(x);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

// Laine-Karras style hash on bit-reversed values: bit j of the result depends only on bits <= j,
// which is what makes it an Owen scramble once the bits are reversed (Vegdahl's constants).
constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Directions of Sobol dimensions 1-3 (Joe and Kuo's new-joe-kuo-6.21201: degree s, coefficients
// a, initial m): direction v_k for index bit k. Dimension 0 is the van der Corput sequence.
struct SobolPolynomial {
    int s;
    uint32_t a, m[3];
};
inline constexpr SobolPolynomial kSobolPolynomials[3] = {
    {1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}};
constexpr uint32_t sobolDirection(int dim, int bit) {
    const SobolPolynomial& p = kSobolPolynomials[dim - 1];
    uint32_t v[32] = {};
    for (int k = 0; k <= bit; ++k) {
        if (k < p.s) {
            v[k] = p.m[k] << (31 - k);
            continue;
        }
        uint32_t x = v[k - p.s] ^ (v[k - p.s] >> p.s);
        for (int j = 1; j < p.s; ++j)
            if ((p.a >> (p.s - 1 - j)) & 1u) x ^= v[k - j];
        v[k] = x;
    }
    return v[bit];
}

// The matrices of dimensions 1-3 applied to each byte of an index, tabulated with the result
// bit-reversed (the form the scramble takes): the product is linear over GF(2), so it is the xor
// of four lookups (instead of a loop over up to 32 index bits, which was the sampler's largest
// cost).
struct SobolByteTables {
    uint32_t t[3][4][256];
    constexpr SobolByteTables() : t{} {
        for (int dim = 1; dim <= 3; ++dim)
            for (int byte = 0; byte < 4; ++byte)
                for (uint32_t b = 0; b < 256; ++b) {
                    uint32_t v = 0;
                    for (int j = 0; j < 8; ++j)
                        if (b >> j & 1u) v ^= sobolDirection(dim, 8 * byte + j);
                    t[dim - 1][byte][b] = reverseBits32(v);
                }
    }
};
inline constexpr SobolByteTables kSobolTables{};

// reverseBits32 of Sobol dimension dim (1-3) at `index`.
constexpr uint32_t sobolDimensionReversed(int dim, uint32_t index) {
    const auto& t = kSobolTables.t[dim - 1];
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^
           t[3][index >> 24];
}

// A 32-bit hash (lowbias32) for deriving the per-pair and per-coordinate seeds.
constexpr uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

struct SobolPair {
    uint32_t x, y;  // fixed point, [0, 2^32) for [0, 1)
};

// The index shuffle alone: an Owen scramble of the index (the hash on its reversed bits, reversed
// back). Both halves of a 4D point share it, so a sampler drawing them finds it once.
constexpr uint32_t shuffledSobolIndex(uint32_t reversedIndex, uint32_t indexSeed) {
    return reverseBits32(laineKarrasPermutation(reversedIndex, indexSeed));
}

// The half of the point at a shuffled index (shuffledSobolIndex).
constexpr SobolPair scrambledSobol4DHalf(uint32_t index, uint32_t coordSeed, bool upper) {
    uint32_t sx = hash32(coordSeed ^ 0xa511e9b3u), sy = hash32(coordSeed ^ 0x63d83595u);
    // Dimension 0 is the bit-reversed index (van der Corput); its scramble reverses the bits back
    // first, so the two reversals cancel. The other dimensions' tables are stored reversed.
    uint32_t x = upper ? sobolDimensionReversed(2, index) : index;
    uint32_t y = sobolDimensionReversed(upper ? 3 : 1, index);
    return {reverseBits32(laineKarrasPermutation(x, sx)),
            reverseBits32(laineKarrasPermutation(y, sy))};
}

// Half `upper` of 4D point `index` (given reversedIndex = reverseBits32(index): a sampler reverses
// its sample index once, not once per pair): dimensions 0-1 (upper false) or 2-3, the index
// shuffled by indexSeed (shared by both halves: they are one 4D net), the coordinates scrambled by
// coordSeed.
constexpr SobolPair shuffledScrambledSobol4DHalf(uint32_t reversedIndex, uint32_t indexSeed,
                                                 uint32_t coordSeed, bool upper) {
    return scrambledSobol4DHalf(shuffledSobolIndex(reversedIndex, indexSeed), coordSeed, upper);
}

// Sample `index` of the pair with this seed: a 4D point's first half whose index shuffle and
// scrambles share the one seed.
constexpr SobolPair shuffledScrambledSobol2D(uint32_t reversedIndex, uint32_t seed) {
    return shuffledScrambledSobol4DHalf(reversedIndex, seed, seed, false);
}

}  // namespace kiln
