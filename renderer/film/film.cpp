#include "renderer/film/film.h"

#include <algorithm>
#include <cmath>

namespace kiln {

Film::Film(int width, int height, const AovRequest& aovs)
    : width_(width),
      height_(height),
      layout_(aovs),
      sum_(size_t(width) * size_t(height)),
      lum_(sum_.size()),
      lumSq_(sum_.size()),
      count_(sum_.size()),
      aov_(sum_.size() * layout_.channels().size()),
      covered_(sum_.size()) {
    if (aovs.has(AovKind::Depth)) depth_.assign(sum_.size(), kInfinity);
    if (aovs.has(AovKind::CryptoObject)) crypto_[0].resize(sum_.size() * kCryptoSlots);
    if (aovs.has(AovKind::CryptoMaterial)) crypto_[1].resize(sum_.size() * kCryptoSlots);
}

bool Film::add(int x, int y, const SampleRecord& r) {
    size_t i = index(x, y);
    uint32_t previous = count_[i]++;
    if (!isFinite(r.L)) return false;
    size_t nc = layout_.channels().size();
    double values[256];
    if (nc) {
        layout_.gather(r, values);
        for (size_t c = 0; c < nc; ++c)
            if (!std::isfinite(values[c])) return false;
    }
    // A transparent background: a ray that left the scene took nothing but the background's light.
    const AovRequest& request = layout_.request();
    bool keepsLight = r.hit || !request.transparent;
    Color L = keepsLight ? r.L : Color(0.0f);
    sum_[i] += Vec3d(L);
    double illum = luminance(L);
    lum_[i] += illum;
    lumSq_[i] += illum * illum;
    double* dst = &aov_[i * nc];
    for (size_t c = 0; c < nc; ++c) {
        if (layout_.channels()[c].firstSample) {
            if (previous == 0) dst[c] = values[c];
        } else if (keepsLight) {
            dst[c] += values[c];
        }
    }
    covered_[i] += r.hit && !(request.transparent && r.hitEmitter);
    if (!depth_.empty() && r.hit)
        depth_[i] = std::min(depth_[i], request.depth == DepthMode::CameraZ ? r.cameraZ : r.depth);
    if (!crypto_[0].empty()) addCrypto(i, 0, r.cryptoObject);
    if (!crypto_[1].empty()) addCrypto(i, 1, r.cryptoMaterial);
    return true;
}

void Film::addCrypto(size_t i, int type, uint32_t id) {
    if (id == 0) return;  // nothing hit
    CryptoSlot* slots = &crypto_[type][i * kCryptoSlots];
    for (int k = 0; k < kCryptoSlots; ++k)
        if (slots[k].id == id || slots[k].count == 0) {
            slots[k].id = id;
            ++slots[k].count;
            return;
        }
    // More distinct ids than slots: this sample's id is not counted (documented limit).
}

float Film::alpha(int x, int y) const {
    size_t i = index(x, y);
    return count_[i] ? float(double(covered_[i]) / double(count_[i])) : 0.0f;
}

Film::CryptoRanks Film::cryptoRanks(int x, int y, int type) const {
    size_t i = index(x, y);
    std::array<CryptoSlot, kCryptoSlots> slots;
    std::copy_n(&crypto_[type][i * kCryptoSlots], kCryptoSlots, slots.begin());
    // Most coverage first; equal coverage by id, so the order never depends on sample order.
    std::sort(slots.begin(), slots.end(), [](const CryptoSlot& a, const CryptoSlot& b) {
        return a.count != b.count ? a.count > b.count : a.id < b.id;
    });
    CryptoRanks ranks{};
    for (int k = 0; k < kCryptoRanks && slots[k].count; ++k)
        ranks[k] = {cryptoIdFloat(slots[k].id), float(double(slots[k].count) / double(count_[i]))};
    return ranks;
}

float Film::aov(int x, int y, size_t c) const {
    size_t i = index(x, y);
    double v = aov_[i * layout_.channels().size() + c];
    if (layout_.channels()[c].firstSample) return count_[i] ? float(v) : -1.0f;
    return count_[i] ? float(v / double(count_[i])) : 0.0f;
}

double Film::luminanceVariance(int x, int y) const {
    size_t i = index(x, y);
    double n = count_[i];
    if (n < 2) return 0.0;
    double s1 = lum_[i], s2 = lumSq_[i];
    return std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)) / n;
}

uint64_t Film::totalSamples() const {
    uint64_t n = 0;
    for (uint32_t c : count_) n += c;
    return n;
}

}  // namespace kiln
