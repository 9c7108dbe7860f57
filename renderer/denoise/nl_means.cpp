#include "renderer/denoise/nl_means.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "renderer/denoise/avx2_clone.h"

namespace kiln::denoise {
namespace {

// Noise-free guides: any real difference gives a zero weight, rounding differences do not.
constexpr float kEpsilon = 1e-10f;
// Before the patch mean: one outlier pixel cannot make a distance infinite.
constexpr float kDistanceClamp = 10000.0f;
// Neighbours that would weigh less than exp(-6.9) = 1e-3 of the centre weigh 0: they change no
// estimate measurably (docs/denoise.md), and the regression skips them.
constexpr float kNegligibleDistance = 6.9f;
constexpr int kTile = 32;
constexpr size_t kPlanePadding = 16;  // floats: one cache line

// Adds channel c's term of the per-pixel distance between the guide values gp and gq (their
// variances vp and vq, already scaled) to d, for n pixels in a row: planar rows, so the loop is
// one stream the compiler vectorises.
inline void addChannelDistance(const float* gp, const float* gq, const float* vp, const float* vq,
                               int n, float* d) {
    for (int x = 0; x < n; ++x) {
        const float a = vp[x], b = vq[x], diff = gp[x] - gq[x];
        d[x] += (diff * diff - (a + std::min(a, b))) / (a + b + kEpsilon);
    }
}

}  // namespace

// The (2F+1)^2 box sums of distance_ (pw x ph) for the tile's tw x th pixels, into patch_: running
// sums along rows, then along columns (double: adding and dropping leaves no drift worth a bit).
KILN_AVX2_CLONE void TileWeights::patchSums(int tw, int th, int pw, int ph, int F) {
    const int n = 2 * F + 1;
    for (int y = 0; y < ph; ++y) {
        const float* d = &distance_[size_t(y) * size_t(pw)];
        float* row = &rows_[size_t(y) * size_t(tw)];
        double sum = 0;
        for (int x = 0; x < n; ++x) sum += d[x];
        row[0] = float(sum);
        for (int x = 1; x < tw; ++x) row[x] = float(sum += double(d[x + n - 1]) - d[x - 1]);
    }
    // Along columns, all columns at once (a row of running sums the compiler vectorises).
    patch_.resize(size_t(tw) * size_t(th));
    columns_.assign(size_t(tw), 0.0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < tw; ++x)
            columns_[size_t(x)] += rows_[size_t(y) * size_t(tw) + size_t(x)];
    for (int x = 0; x < tw; ++x) patch_[size_t(x)] = float(columns_[size_t(x)]);
    for (int y = 1; y < th; ++y) {
        const float* enter = &rows_[size_t(y + n - 1) * size_t(tw)];
        const float* leave = &rows_[size_t(y - 1) * size_t(tw)];
        float* out = &patch_[size_t(y) * size_t(tw)];
        for (int x = 0; x < tw; ++x)
            out[x] = float(columns_[size_t(x)] += double(enter[x]) - leave[x]);
    }
}

// The guide and its scaled variance around the tile (F + R beyond it on each side), planar per
// channel, coordinates clamped to the image as the patches read them.
void TileWeights::copyRegion(const Image& guide, const Image& variance, const Rect& tile,
                             int margin, float varianceScale) {
    const int nc = guide.channels;
    imageWidth_ = guide.width, imageHeight_ = guide.height;
    regionWidth_ = tile.width() + 2 * margin;
    const int rh = tile.height() + 2 * margin;
    const size_t plane = size_t(regionWidth_) * size_t(rh);
    region_.resize(2 * size_t(nc) * plane);
    for (int y = 0; y < rh; ++y) {
        const int gy = std::clamp(tile.y0 - margin + y, 0, guide.height - 1);
        for (int x = 0; x < regionWidth_; ++x) {
            const int gx = std::clamp(tile.x0 - margin + x, 0, guide.width - 1);
            const size_t at = (size_t(gy) * size_t(guide.width) + size_t(gx)) * size_t(nc);
            const size_t local = size_t(y) * size_t(regionWidth_) + size_t(x);
            for (int c = 0; c < nc; ++c) {
                region_[size_t(c) * plane + local] = guide.values[at + size_t(c)];
                region_[size_t(nc + c) * plane + local] =
                    variance.values[at + size_t(c)] * varianceScale;
            }
        }
    }
}

KILN_AVX2_CLONE void TileWeights::compute(const Image& guide, const Image& variance,
                                          const Rect& tile, const NlMeansParams& params) {
    const int R = params.windowRadius, F = params.patchRadius;
    const int tw = tile.width(), th = tile.height(), pw = tw + 2 * F, ph = th + 2 * F;
    tile_ = tile, radius_ = R, pixels_ = size_t(tw) * size_t(th);
    // Planes 4 KiB apart would share cache sets: reading one pixel's weights across the offsets
    // would evict itself.
    plane_ = pixels_ + kPlanePadding;
    patchDistances_.resize(size_t(offsets()) * plane_);
    distance_.resize(size_t(pw) * size_t(ph));
    rows_.resize(size_t(tw) * size_t(ph));
    const float norm = 1.0f / float((2 * F + 1) * (2 * F + 1));
    const int nc = guide.channels;
    copyRegion(guide, variance, tile, F + R, params.varianceScale);
    const size_t rw = size_t(regionWidth_), plane = rw * size_t(th + 2 * (F + R));
    int o = 0;
    for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx, ++o) {
            for (int y = 0; y < ph; ++y) {
                float* d = &distance_[size_t(y) * pw];
                std::fill(d, d + pw, 0.0f);
                const size_t p = size_t(y + R) * rw + size_t(R);  // the patch pixel, and q
                const size_t q = size_t(y + R + dy) * rw + size_t(R + dx);
                for (int c = 0; c < nc; ++c) {
                    const float* g = &region_[size_t(c) * plane];
                    const float* v = &region_[size_t(nc + c) * plane];
                    addChannelDistance(g + p, g + q, v + p, v + q, pw, d);
                }
                for (int x = 0; x < pw; ++x) d[x] = std::min(d[x] / float(nc), kDistanceClamp);
            }
            patchSums(tw, th, pw, ph, F);
            float* out = &patchDistances_[size_t(o) * plane_];
            for (size_t i = 0; i < pixels_; ++i) out[i] = std::max(patch_[i] * norm, 0.0f);
        }
}

KILN_AVX2_CLONE void TileWeights::weigh(float k) {
    const int R = radius_, tw = tile_.width(), th = tile_.height();
    const float invK2 = 1.0f / (k * k);
    weights_.assign(size_t(offsets()) * plane_, 0.0f);
    int o = 0;
    for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx, ++o) {
            const float* distance = &patchDistances_[size_t(o) * plane_];
            float* out = &weights_[size_t(o) * plane_];
            // The tile pixels whose neighbour at (dx, dy) lies inside the image.
            const int x0 = std::max(0, -dx - tile_.x0),
                      x1 = std::min(tw, imageWidth_ - dx - tile_.x0);
            const int y0 = std::max(0, -dy - tile_.y0),
                      y1 = std::min(th, imageHeight_ - dy - tile_.y0);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const float a = distance[size_t(y) * tw + x] * invK2;
                    if (a < kNegligibleDistance) out[size_t(y) * tw + x] = std::exp(-a);
                }
        }
}

namespace {

// Whether the variance is 0 everywhere within margin of the tile.
bool noiseFree(const Image& variance, const Rect& tile, int margin) {
    const int x0 = std::max(0, tile.x0 - margin), x1 = std::min(variance.width, tile.x1 + margin);
    const int y0 = std::max(0, tile.y0 - margin), y1 = std::min(variance.height, tile.y1 + margin);
    for (int y = y0; y < y1; ++y) {
        const float* v = variance.at(x0, y);
        for (size_t i = 0; i < size_t(x1 - x0) * size_t(variance.channels); ++i)
            if (v[i] != 0) return false;
    }
    return true;
}

}  // namespace

Image nlMeans(const Image& image, const Image& guide, const Image& variance,
              const NlMeansParams& params) {
    const int nc = image.channels, R = params.windowRadius;
    Image out(image.width, image.height, nc);
    const std::vector<Rect> tiles = tilesOf(image.width, image.height, kTile);
    tbb::enumerable_thread_specific<TileWeights> scratch;
    tbb::enumerable_thread_specific<std::vector<double>> sums;
    tbb::parallel_for(size_t(0), tiles.size(), [&](size_t t) {
        const Rect& tile = tiles[t];
        if (params.keepNoiseFree &&
            noiseFree(variance, tile, params.windowRadius + params.patchRadius)) {
            for (int y = tile.y0; y < tile.y1; ++y)
                std::copy_n(image.at(tile.x0, y), size_t(tile.width()) * size_t(nc),
                            out.at(tile.x0, y));
            return;
        }
        TileWeights& weights = scratch.local();
        weights.compute(guide, variance, tile, params);
        weights.weigh(params.k);
        // Offset by offset, every pixel of the tile: each pixel's sum still adds its neighbours
        // in offset order.
        const size_t pixels = size_t(tile.width()) * size_t(tile.height());
        std::vector<double>& sum = sums.local();
        sum.assign(pixels * size_t(nc + 1), 0.0);  // per pixel: the channels, then the weight
        int o = 0;
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx, ++o) {
                const float* w = weights.offset(o);
                for (int y = tile.y0; y < tile.y1; ++y) {
                    const size_t row = size_t(y - tile.y0) * size_t(tile.width());
                    for (int x = tile.x0; x < tile.x1; ++x) {
                        const size_t local = row + size_t(x - tile.x0);
                        const float wq = w[local];
                        if (wq <= 0) continue;
                        const float* q = image.at(x + dx, y + dy);
                        double* s = &sum[local * size_t(nc + 1)];
                        for (int c = 0; c < nc; ++c) s[c] += double(wq) * q[c];
                        s[nc] += wq;
                    }
                }
            }
        // The centre's own weight is 1: the total is >= 1.
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const double* s =
                    &sum[(size_t(y - tile.y0) * size_t(tile.width()) + size_t(x - tile.x0)) *
                         size_t(nc + 1)];
                float* px = out.at(x, y);
                for (int c = 0; c < nc; ++c) px[c] = float(s[c] / s[nc]);
            }
    });
    return out;
}

}  // namespace kiln::denoise
