// Piecewise-constant 1D and 2D distributions for importance sampling (lights by power, environment
// maps).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace kiln {

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
        float width = cdf_[i + 1] - cdf_[i];
        float du = width > 0 ? (u - cdf_[i]) / width : 0.5f;
        pdf = width * float(f_.size());
        return std::min((float(i) + du) / float(f_.size()), 1.0f - 1e-7f);
    }
    float density(size_t i) const { return pmf(i) * float(f_.size()); }
    float integral() const { return uniform_ ? 0.0f : total_ / float(f_.size()); }

  private:
    // The bin u falls in: the first i with cdf_[i + 1] > u (upper_bound), then past zero-width
    // bins. The guide table (Chen and Asau's cutpoint method) starts the search at the answer for
    // the bottom of u's bucket, and a short walk finds the same bin a binary search would: expected
    // O(1) per sample for any distribution (an environment map samples a row and a column per
    // light sample), and bit for bit the same choice.
    size_t index(float u) const {
        size_t bucket = u >= 0 ? size_t(u * float(guide_.size())) : 0;  // NaN: bucket 0
        size_t p = guide_.empty() ? 0 : guide_[std::min(guide_.size() - 1, bucket)];
        while (p > 0 && cdf_[p - 1] > u) --p;
        while (p < cdf_.size() && cdf_[p] <= u) ++p;
        size_t i = std::clamp<size_t>(p, 1, f_.size()) - 1;
        while (i + 1 < f_.size() && cdf_[i + 1] - cdf_[i] <= 0) ++i;  // skip zero-width bins
        return i;
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

// f(u, v) on a w x h grid (row v, column u).
class Distribution2D {
  public:
    Distribution2D() = default;
    Distribution2D(const std::vector<float>& f, size_t w, size_t h) : w_(w), h_(h) {
        std::vector<float> rowSums(h);
        for (size_t v = 0; v < h; ++v) {
            std::vector<float> row(f.begin() + long(v * w), f.begin() + long((v + 1) * w));
            rows_.emplace_back(row);
            rowSums[v] = rows_.back().integral();
        }
        marginal_ = Distribution1D(rowSums);
    }
    // (u, v) in [0,1)^2 and the density with respect to the unit square.
    void sample(float u1, float u2, float& u, float& v, float& pdf) const {
        float pdfV, pdfU;
        size_t iv, iu;
        v = marginal_.sampleContinuous(u2, pdfV, iv);
        u = rows_[iv].sampleContinuous(u1, pdfU, iu);
        pdf = pdfV * pdfU;
    }
    float pdf(float u, float v) const {
        size_t iu = std::min(size_t(u * float(w_)), w_ - 1),
               iv = std::min(size_t(v * float(h_)), h_ - 1);
        return marginal_.density(iv) * rows_[iv].density(iu);
    }

  private:
    size_t w_ = 0, h_ = 0;
    std::vector<Distribution1D> rows_;
    Distribution1D marginal_;
};

}  // namespace kiln
