// A piecewise-constant 1D distribution for importance sampling (lights by power, triangles by area,
// an environment map's rows).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace kiln {

// The bin of a normalised CDF (n + 1 points) that u falls in, walking from p (the upper_bound in
// cdf of a value at or just below u): the first i with cdf[i + 1] > u, then past zero-width bins.
inline size_t cdfWalk(std::span<const float> cdf, size_t p, float u) {
    const size_t n = cdf.size() - 1;
    while (p > 0 && cdf[p - 1] > u) --p;
    while (p < cdf.size() && cdf[p] <= u) ++p;
    size_t i = std::clamp<size_t>(p, 1, n) - 1;
    while (i + 1 < n && cdf[i + 1] - cdf[i] <= 0) ++i;  // skip zero-width bins
    return i;
}

// Where u lies in bin i (its CDF interval [lo, hi) of n bins), as a position in [0, 1), and the
// density there.
inline float positionInBin(size_t i, float lo, float hi, size_t n, float u, float& pdf) {
    const float width = hi - lo;
    const float du = width > 0 ? (u - lo) / width : 0.5f;
    pdf = width * float(n);
    return std::min((float(i) + du) / float(n), 1.0f - 1e-7f);
}

class Distribution1D {
  public:
    Distribution1D() = default;
    explicit Distribution1D(std::vector<float> f) : f_(std::move(f)), cdf_(f_.size() + 1, 0.0f) {
        for (size_t i = 0; i < f_.size(); ++i) cdf_[i + 1] = cdf_[i] + std::max(0.0f, f_[i]);
        total_ = cdf_.back();
        if (total_ <= 0) {  // all zero: uniform, so sampling still works
            for (size_t i = 0; i < f_.size(); ++i) cdf_[i + 1] = float(i + 1);
            total_ = float(f_.size());
            uniform_ = true;
        }
        for (float& c : cdf_) c /= total_;
        buildGuide();
    }
    size_t size() const { return f_.size(); }
    // Discrete sample: index and its probability.
    size_t sampleDiscrete(float u, float& pmf) const {
        size_t i = index(u);
        pmf = this->pmf(i);
        return i;
    }
    float pmf(size_t i) const { return cdf_[i + 1] - cdf_[i]; }
    // Continuous sample in [0,1): position and density.
    float sampleContinuous(float u, float& pdf, size_t& i) const {
        i = index(u);
        return positionInBin(i, cdf_[i], cdf_[i + 1], f_.size(), u, pdf);
    }
    float density(size_t i) const { return pmf(i) * float(f_.size()); }
    float integral() const { return uniform_ ? 0.0f : total_ / float(f_.size()); }

  private:
    friend class Distribution1DRows;
    // The bin u falls in: the first i with cdf_[i + 1] > u (upper_bound), then past zero-width
    // bins. The guide table (Chen and Asau's cutpoint method) starts the search at the answer for
    // the bottom of u's bucket, and a short walk finds the same bin a binary search would, bit for
    // bit. Expected O(1) for any distribution: with as many buckets as bins, the walk from a
    // bucket passes only the CDF points inside it, n points over n buckets, so on average fewer
    // than two steps per sample.
    size_t index(float u) const { return cdfWalk(cdf_, guideStart(u), u); }
    size_t guideStart(float u) const {
        size_t bucket = u >= 0 ? size_t(u * float(guide_.size())) : 0;  // NaN: bucket 0
        return guide_.empty() ? 0 : guide_[std::min(guide_.size() - 1, bucket)];
    }
    void buildGuide() {
        guide_.assign(std::max<size_t>(1, f_.size()), 0);
        size_t p = 0;
        for (size_t k = 0; k < guide_.size(); ++k) {
            float lo = float(k) / float(guide_.size());
            while (p < cdf_.size() && cdf_[p] <= lo) ++p;
            guide_[k] = uint32_t(p);
        }
    }
    std::vector<float> f_, cdf_;
    std::vector<uint32_t> guide_;  // per bucket of [0, 1): upper_bound of its bottom in cdf_
    float total_ = 0;
    bool uniform_ = false;
};

// Equal-sized distributions in flat arrays (an environment map's rows, one per row of texels), each
// drawn exactly as a Distribution1D of its weights draws, bit for bit. Each guide bucket also holds
// the CDF points of the bin its bottom falls in and of the next bin, so a draw that lands in either
// (every draw, for bins at least a bucket wide) reads one 16-byte entry; the others walk the row's
// CDF as Distribution1D does. A Distribution1D per row costs three dependent cache misses (the
// object, its guide, its CDF) on a map too large for the cache; with one bin per entry, half the
// draws of an evenly lit row walked (a bucket's bottom bin ends inside it), a second miss.
class Distribution1DRows {
  public:
    Distribution1DRows() = default;
    // rows x n weights, row after row.
    Distribution1DRows(const std::vector<float>& f, size_t n, size_t rows) : n_(n) {
        cdf_.reserve(rows * (n + 1));
        guide_.reserve(rows * n);
        for (size_t r = 0; r < rows; ++r) {
            Distribution1D row(
                std::vector<float>(f.begin() + long(r * n), f.begin() + long((r + 1) * n)));
            cdf_.insert(cdf_.end(), row.cdf_.begin(), row.cdf_.end());
            integrals_.push_back(row.integral());
            for (uint32_t p : row.guide_) {
                bool inside = p >= 1 && p <= n;  // else no first bin: always walk
                bool next = inside && p < n;     // a second bin follows the first
                guide_.push_back({p, inside ? row.cdf_[p - 1] : 1.0f, inside ? row.cdf_[p] : 0.0f,
                                  next ? row.cdf_[p + 1] : 0.0f});
            }
        }
    }
    // A Distribution1D's sampleContinuous on row r.
    float sampleContinuous(size_t r, float u, float& pdf, size_t& i) const {
        size_t bucket = u >= 0 ? std::min(n_ - 1, size_t(u * float(n_))) : 0;  // NaN: bucket 0
        const Bucket& b = guide_[r * n_ + bucket];
        if (b.lo <= u && u < b.mid) {  // the walk would stay at b.p
            i = b.p - 1;
            return positionInBin(i, b.lo, b.mid, n_, u, pdf);
        }
        if (b.mid <= u && u < b.hi) {  // the walk would take one step
            i = b.p;
            return positionInBin(i, b.mid, b.hi, n_, u, pdf);
        }
        std::span<const float> cdf(cdf_.data() + r * (n_ + 1), n_ + 1);
        i = cdfWalk(cdf, b.p, u);
        return positionInBin(i, cdf[i], cdf[i + 1], n_, u, pdf);
    }
    // Asks memory for the guide entry a draw of u on row r reads first (sampling many points at
    // once: their cache misses then overlap instead of following one another).
    void prefetch(size_t r, float u) const {
        size_t bucket = u >= 0 ? std::min(n_ - 1, size_t(u * float(n_))) : 0;
        __builtin_prefetch(&guide_[r * n_ + bucket]);
    }
    // Asks memory for what density(r, i) reads.
    void prefetchDensity(size_t r, size_t i) const { __builtin_prefetch(&cdf_[r * (n_ + 1) + i]); }
    // Row r's Distribution1D::integral (the rows' marginal weights).
    float integral(size_t r) const { return integrals_[r]; }
    float density(size_t r, size_t i) const {
        const float* cdf = cdf_.data() + r * (n_ + 1);
        return (cdf[i + 1] - cdf[i]) * float(n_);
    }

  private:
    struct Bucket {
        uint32_t p;  // upper_bound of the bucket's bottom in the row's CDF
        // CDF intervals of bin p - 1, [lo, mid) (lo > mid: none), and bin p, [mid, hi) (hi <= mid:
        // none).
        float lo, mid, hi;
    };
    size_t n_ = 0;
    std::vector<float> cdf_;     // rows x (n + 1)
    std::vector<Bucket> guide_;  // rows x n
    std::vector<float> integrals_;
};

}  // namespace kiln
