#include "renderer/film/film.h"

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
      aov_(sum_.size() * layout_.channels().size()) {}

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
    sum_[i] += Vec3d(r.L);
    double illum = luminance(r.L);
    lum_[i] += illum;
    lumSq_[i] += illum * illum;
    double* dst = aov_.data() + i * nc;  // no element to index when there are no AOVs
    for (size_t c = 0; c < nc; ++c) {
        if (layout_.channels()[c].firstSample) {
            if (previous == 0) dst[c] = values[c];
        } else {
            dst[c] += values[c];
        }
    }
    return true;
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
