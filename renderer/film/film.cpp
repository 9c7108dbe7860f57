#include "renderer/film/film.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kiln {
namespace {

// A half-buffer value into the fixed-point range; one beyond it (the square of a channel far above
// the luminance that was checked) is held at the range's end.
FixedSum heldInRange(double v) {
    FixedSum f = 0;
    if (!toFixed(v, f)) toFixed(std::nextafter(kMaxSampleValue, 0.0), f);
    return f;
}

}  // namespace

Film::Film(int width, int height, const AovRequest& aovs)
    : width_(width), height_(height), layout_(aovs) {
    for (const AovChannel& c : layout_.channels())
        slot_.push_back(c.firstSample ? firstChannels_++ : sumChannels_++);
    size_t n = size_t(width) * size_t(height);
    sum_.resize(3 * n);
    lum_.resize(n);
    lumSq_.resize(n);
    count_.resize(n);
    aovSum_.resize(n * sumChannels_);
    aovFirst_.resize(n * firstChannels_);
    converged_.resize(n);
    covered_.resize(n);
    if (aovs.has(AovKind::Depth)) depth_.assign(n, kInfinity);
    if (aovs.has(AovKind::CryptoObject)) crypto_[0].resize(n * kCryptoSlots);
    if (aovs.has(AovKind::CryptoMaterial)) crypto_[1].resize(n * kCryptoSlots);
    if (aovs.has(AovKind::DenoiseHalves)) {
        halfStride_ = kHalfSums + kLayerHalfSums * layout_.denoisedLayers().size();
        halves_.resize(n * 2 * halfStride_);
        halfCount_.resize(n * 2);
    }
}

void Film::setScaleExponent(int exponent) {
    scaleExponent_ = exponent;
    down_ = std::ldexp(1.0, -exponent), up_ = std::ldexp(1.0, exponent);
}

std::vector<FilmBuffer> Film::buffers() {
    auto sums = [](const char* name, std::vector<FixedSum>& v, size_t per) {
        return FilmBuffer{name, Accumulation::Sum, sizeof(FixedSum), uint32_t(per), v.data()};
    };
    return {
        sums("beauty", sum_, 3),
        sums("luminance", lum_, 1),
        sums("luminance_squared", lumSq_, 1),
        sums("aov", aovSum_, sumChannels_),
        {"aov_first", Accumulation::FirstSample, sizeof(double), uint32_t(firstChannels_),
         aovFirst_.data()},
        {"adaptive_converged", Accumulation::Flag, 1, 1, converged_.data()},
        {"covered", Accumulation::Count, sizeof(uint32_t), 1, covered_.data()},
        {"depth", Accumulation::Min, sizeof(float), depth_.empty() ? 0u : 1u, depth_.data()},
        {"crypto_object", Accumulation::CryptoIds, sizeof(CryptoSlot),
         crypto_[0].empty() ? 0u : uint32_t(kCryptoSlots), crypto_[0].data()},
        {"crypto_material", Accumulation::CryptoIds, sizeof(CryptoSlot),
         crypto_[1].empty() ? 0u : uint32_t(kCryptoSlots), crypto_[1].data()},
        sums("denoise_halves", halves_, halves_.empty() ? 0 : 2 * halfStride_),
        {"denoise_half_samples", Accumulation::Count, sizeof(uint32_t),
         halfCount_.empty() ? 0u : 2u, halfCount_.data()},
        // Last: merging reads the counts before the shard's are added (FirstSample).
        {"samples", Accumulation::Count, sizeof(uint32_t), 1, count_.data()},
    };
}

bool Film::add(int x, int y, const SampleRecord& r, int sample) {
    size_t i = index(x, y);
    uint32_t previous = count_[i]++;
    const int half = halfOfSample(sample >= 0 ? uint32_t(sample) : previous);
    // Counted like count_ (a dropped sample counts as black), so the halves add up to the pixel.
    if (!halfCount_.empty()) ++halfCount_[2 * i + size_t(half)];
    size_t nc = layout_.channels().size();
    double values[256];
    if (nc) layout_.gather(r, values);
    // A transparent background: a ray that left the scene took nothing but the background's light.
    const AovRequest& request = layout_.request();
    const bool keepsLight = r.hit || !request.transparent;
    const Color L = keepsLight ? r.L : Color(0.0f);
    // Every value converted before any is added: a sample enters the film whole or not at all.
    FixedSum fixed[256 + 5];
    // Light is held in the film's scale; powers of two, so the scaling itself is exact.
    double illum = luminance(L) * down_;
    if (!toFixed(L.x * down_, fixed[0]) || !toFixed(L.y * down_, fixed[1]) ||
        !toFixed(L.z * down_, fixed[2]) || !toFixed(illum, fixed[3]) ||
        !toFixed(illum * illum, fixed[4]))
        return false;
    for (size_t c = 0; c < nc; ++c)
        if (!toFixed(layout_.channels()[c].radiance ? values[c] * down_ : values[c], fixed[5 + c]))
            return false;
    for (int k = 0; k < 3; ++k) sum_[3 * i + size_t(k)] += fixed[k];
    lum_[i] += fixed[3];
    lumSq_[i] += fixed[4];
    // .data() + offset: no element to index when there are no AOVs (UBSan).
    FixedSum* sums = aovSum_.data() + i * sumChannels_;
    double* firsts = aovFirst_.data() + i * firstChannels_;
    for (size_t c = 0; c < nc; ++c) {
        if (!layout_.channels()[c].firstSample) {
            if (keepsLight) sums[slot_[c]] += fixed[5 + c];
        } else if (previous == 0) {
            firsts[slot_[c]] = values[c];
        }
    }
    covered_[i] += r.hit && !(request.transparent && r.hitEmitter);
    if (!depth_.empty() && r.hit)
        depth_[i] = std::min(depth_[i], request.depth == DepthMode::CameraZ ? r.cameraZ : r.depth);
    if (!crypto_[0].empty()) addCrypto(i, 0, r.cryptoObject);
    if (!crypto_[1].empty()) addCrypto(i, 1, r.cryptoMaterial);
    if (!halves_.empty()) {
        addToHalf(i, half, fixed, L * float(down_), r);
        // Light the beauty drops (a transparent background) leaves the layers' sums too.
        if (keepsLight)
            addLayersToHalf(&halves_[(2 * i + size_t(half)) * halfStride_], fixed + 5, values);
    }
    return true;
}

// The denoised layers' colour (already converted in fixed, the layout's order) and squares.
void Film::addLayersToHalf(FixedSum* sums, const FixedSum* fixed, const double* values) const {
    FixedSum* at = sums + kHalfSums;
    for (const DenoisedLayer& layer : layout_.denoisedLayers()) {
        for (size_t k = 0; k < 3; ++k) {
            at[k] += fixed[layer.channel + k];
            const double v = values[layer.channel + k] * down_;
            at[3 + k] += heldInRange(v * v);
        }
        at += kLayerHalfSums;
    }
}

void Film::addToHalf(size_t i, int half, const FixedSum colour[3], const Color& scaled,
                     const SampleRecord& r) {
    FixedSum* sums = &halves_[(2 * i + size_t(half)) * halfStride_];
    double values[kHalfSums];
    for (int k = 0; k < 3; ++k) values[3 + k] = double(scaled[k]) * double(scaled[k]);
    halfFeatures(r, values + 6);
    for (int k = 0; k < 3; ++k) sums[k] += colour[k];
    // Features are finite and in range (halfFeatures); squares may not be.
    for (int k = 3; k < kHalfSums; ++k) sums[k] += heldInRange(values[k]);
}

void Film::halfMean(int x, int y, int h, float out[kHalfChannels]) const {
    size_t at = 2 * index(x, y) + size_t(h);
    double n = halfCount_[at];
    const FixedSum* sums = &halves_[at * halfStride_];
    for (int k = 0; k < 3; ++k)
        halfMeanAndVariance(fromFixed(sums[k]), fromFixed(sums[3 + k]), n, up_, out[k], out[3 + k]);
    for (int k = 6; k < kHalfChannels; ++k) out[k] = n > 0 ? float(fromFixed(sums[k]) / n) : 0.0f;
}

void Film::layerHalfMean(int x, int y, int h, size_t layer, float out[kLayerHalfChannels]) const {
    size_t at = 2 * index(x, y) + size_t(h);
    const FixedSum* sums = &halves_[at * halfStride_ + kHalfSums + layer * kLayerHalfSums];
    for (int k = 0; k < 3; ++k)
        halfMeanAndVariance(fromFixed(sums[k]), fromFixed(sums[3 + k]), halfCount_[at], up_, out[k],
                            out[3 + k]);
}

namespace {

// One (id, count) into a pixel's slots: the same id adds its count, a new one takes a free slot.
// With every slot taken the count is dropped (a documented limit: ids beyond kCryptoSlots).
void addToSlots(CryptoSlot* slots, uint32_t id, uint32_t count) {
    if (id == 0 || count == 0) return;  // nothing hit
    for (int k = 0; k < kCryptoSlots; ++k)
        if (slots[k].id == id || slots[k].count == 0) {
            slots[k].id = id;
            slots[k].count += count;
            return;
        }
}

}  // namespace

void Film::addCrypto(size_t i, int type, uint32_t id) {
    addToSlots(&crypto_[type][i * kCryptoSlots], id, 1);
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

Color Film::pixel(int x, int y) const {
    size_t i = index(x, y);
    if (!count_[i]) return Color(0.0f);
    double n = count_[i];
    return Color(float(fromFixed(sum_[3 * i]) * up_ / n),
                 float(fromFixed(sum_[3 * i + 1]) * up_ / n),
                 float(fromFixed(sum_[3 * i + 2]) * up_ / n));
}

float Film::aov(int x, int y, size_t c) const {
    size_t i = index(x, y);
    if (layout_.channels()[c].firstSample)
        return count_[i] ? float(aovFirst_[i * firstChannels_ + slot_[c]]) : -1.0f;
    if (!count_[i]) return 0.0f;
    double sum = fromFixed(aovSum_[i * sumChannels_ + slot_[c]]);
    return float((layout_.channels()[c].radiance ? sum * up_ : sum) / double(count_[i]));
}

double Film::luminanceVariance(int x, int y) const {
    size_t i = index(x, y);
    double n = count_[i];
    if (n < 2) return 0.0;
    double s1 = fromFixed(lum_[i]), s2 = fromFixed(lumSq_[i]);
    return std::max(0.0, (s2 - s1 * s1 / n) / (n - 1)) / n * up_ * up_;
}

uint64_t Film::totalSamples() const {
    uint64_t n = 0;
    for (uint32_t c : count_) n += c;
    return n;
}

void combineRun(const FilmBuffer& dst, const void* src, size_t dstPixel, size_t pixels,
                const uint32_t* dstCounts) {
    size_t per = dst.perPixel;
    switch (dst.rule) {
        case Accumulation::Sum: {
            auto* d = static_cast<FixedSum*>(dst.data) + dstPixel * per;
            auto* s = static_cast<const FixedSum*>(src);
            for (size_t k = 0; k < pixels * per; ++k) d[k] += s[k];
            break;
        }
        case Accumulation::Count: {
            auto* d = static_cast<uint32_t*>(dst.data) + dstPixel * per;
            auto* s = static_cast<const uint32_t*>(src);
            for (size_t k = 0; k < pixels * per; ++k) d[k] += s[k];
            break;
        }
        case Accumulation::FirstSample: {
            auto* d = static_cast<double*>(dst.data) + dstPixel * per;
            auto* s = static_cast<const double*>(src);
            for (size_t p = 0; p < pixels; ++p)
                if (dstCounts[dstPixel + p] == 0) std::copy_n(s + p * per, per, d + p * per);
            break;
        }
        case Accumulation::Min: {
            auto* d = static_cast<float*>(dst.data) + dstPixel * per;
            auto* s = static_cast<const float*>(src);
            for (size_t k = 0; k < pixels * per; ++k) d[k] = std::min(d[k], s[k]);
            break;
        }
        case Accumulation::CryptoIds: {
            auto* d = static_cast<CryptoSlot*>(dst.data) + dstPixel * per;
            auto* s = static_cast<const CryptoSlot*>(src);
            for (size_t p = 0; p < pixels; ++p)
                for (size_t k = 0; k < per; ++k)
                    addToSlots(d + p * per, s[p * per + k].id, s[p * per + k].count);
            break;
        }
        case Accumulation::Flag: {
            auto* d = static_cast<uint8_t*>(dst.data) + dstPixel;
            auto* s = static_cast<const uint8_t*>(src);
            for (size_t k = 0; k < pixels; ++k) d[k] |= s[k];
            break;
        }
    }
}

size_t Film::placeShard(int originX, int originY, int shardWidth, int shardHeight, int fullWidth,
                        int fullHeight) const {
    int dx = originX - originX_, dy = originY - originY_;
    if (dx < 0 || dy < 0 || dx + shardWidth > width_ || dy + shardHeight > height_ ||
        fullWidth != this->fullWidth() || fullHeight != this->fullHeight())
        throw std::invalid_argument("shard region lies outside the merged image");
    return index(dx, dy);
}

}  // namespace kiln
