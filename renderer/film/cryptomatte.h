// Cryptomatte ids (Psyop's open convention, specification 1.1.0): a name's MurmurHash3_x86_32
// (seed 0) turned into a float bit for bit with the exponent clamped to [1, 254], so no id is a
// NaN, an infinity, a denormal or zero (zero means "no object").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace kiln {

// Ranks written per Cryptomatte type: 3 RGBA layers of two (id, coverage) pairs, the
// specification's suggested default.
constexpr int kCryptoRanks = 6;
// Distinct ids a pixel counts before ranking (ids beyond these count as uncovered).
constexpr int kCryptoSlots = 8;

uint32_t murmurHash3(std::string_view text);
// The id as the float bits written into the image.
uint32_t cryptoIdBits(std::string_view name);
float cryptoIdFloat(uint32_t bits);
// The manifest's value for an id: its float bits as 8 lower-case hex digits.
std::string cryptoHex(uint32_t bits);
// The metadata key of a Cryptomatte layer ("cryptomatte/KEY/name"): the first 7 hex digits of the
// layer name's hash, stable from frame to frame (as Blender makes it).
std::string cryptoLayerKey(std::string_view layerName);
// {"name": "hex", ...} for every name (duplicates share an id, as the specification intends).
std::string cryptoManifest(const std::vector<std::string>& names);

// One pixel's (id, sample count) pairs for one Cryptomatte type.
struct CryptoSlot {
    uint32_t id = 0;
    uint32_t count = 0;
};

}  // namespace kiln
