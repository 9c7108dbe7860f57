#include "renderer/film/cryptomatte.h"

#include <fmt/format.h>
#include <murmurhash.h>

#include <cstring>
#include <nlohmann/json.hpp>

namespace kiln {

uint32_t murmurHash3(std::string_view text) {
    uint32_t out[1];
    lmmh_x86_32(text.data(), unsigned(text.size()), 0, out);
    return out[0];
}

uint32_t cryptoIdBits(std::string_view name) {
    uint32_t hash = murmurHash3(name);
    uint32_t exponent = std::clamp((hash >> 23) & 0xffu, 1u, 254u);
    return (hash & 0x807fffffu) | (exponent << 23);
}

float cryptoIdFloat(uint32_t bits) {
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

std::string cryptoHex(uint32_t bits) { return fmt::format("{:08x}", bits); }

std::string cryptoLayerKey(std::string_view layerName) {
    return cryptoHex(murmurHash3(layerName)).substr(0, 7);
}

std::string cryptoManifest(const std::vector<std::string>& names) {
    nlohmann::json manifest = nlohmann::json::object();
    for (const std::string& name : names) manifest[name] = cryptoHex(cryptoIdBits(name));
    // Names are bytes from the scene file: invalid UTF-8 is replaced, never a throw.
    return manifest.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace kiln
