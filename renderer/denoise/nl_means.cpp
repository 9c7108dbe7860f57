#include "renderer/denoise/nl_means.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace kiln::denoise {
namespace {

// Noise-free guides: any real difference gives a zero weight, rounding differences do not.
constexpr float kEpsilon = 1e-10f;
// Before the patch mean: one outlier pixel cannot make a distance infinite.
constexpr float kDistanceClamp = 10000.0f;
constexpr int kTile = 32;

// The per-pixel distance between guide values p and q (their channels averaged), with their
// variances vp and vq.
inline float pixelDistance(const float* gp, const float* gq, const float* vp, const float* vq,
                           int channels, float k2, float scale) {
    float sum = 0;
    for (int c = 0; c < channels; ++c) {
        float a = vp[c] * scale, b = vq[c] * scale, d = gp[c] - gq[c];
        sum += (d * d - (a + std::min(a, b))) / (k2 * (a + b) + kEpsilon);
    }
    return std::min(sum / float(channels), kDistanceClamp);
}

// Pixel indices of the coordinates [from, from + n), clamped to [0, size).
void clampedIndices(int from, int n, int size, std::vector<int>& out) {
    out.resize(size_t(n));
    for (int i = 0; i < n; ++i) out[size_t(i)] = std::clamp(from + i, 0, size - 1);
}

}  // namespace

// The (2F+1)^2 box sums of distance_ (pw x ph) for the tile's tw x th pixels, into patch_: running
// sums along rows, then along columns (double: adding and dropping leaves no drift worth a bit).
void TileWeights::patchSums(int tw, int th, int pw, int ph, int F) {
    const int n = 2 * F + 1;
    for (int y = 0; y < ph; ++y) {
        const float* d = &distance_[size_t(y) * size_t(pw)];
        float* row = &rows_[size_t(y) * size_t(tw)];
        double sum = 0;
        for (int x = 0; x < n; ++x) sum += d[x];
        row[0] = float(sum);
        for (int x = 1; x < tw; ++x) row[x] = float(sum += double(d[x + n - 1]) - d[x - 1]);
    }
    patch_.resize(size_t(tw) * size_t(th));
    for (int x = 0; x < tw; ++x) {
        double sum = 0;
        for (int y = 0; y < n; ++y) sum += rows_[size_t(y) * size_t(tw) + size_t(x)];
        patch_[size_t(x)] = float(sum);
        for (int y = 1; y < th; ++y)
            patch_[size_t(y) * size_t(tw) + size_t(x)] =
                float(sum += double(rows_[size_t(y + n - 1) * size_t(tw) + size_t(x)]) -
                             rows_[size_t(y - 1) * size_t(tw) + size_t(x)]);
    }
}

void TileWeights::compute(const Image& guide, const Image& variance, const Rect& tile,
                          const NlMeansParams& params) {
    const int R = params.windowRadius, F = params.patchRadius;
    const int tw = tile.width(), th = tile.height(), pw = tw + 2 * F, ph = th + 2 * F;
    radius_ = R, pixels_ = size_t(tw) * size_t(th);
    weights_.assign(size_t(offsets()) * pixels_, 0.0f);
    distance_.resize(size_t(pw) * size_t(ph));
    rows_.resize(size_t(tw) * size_t(ph));
    const float k2 = params.k * params.k, norm = 1.0f / float((2 * F + 1) * (2 * F + 1));
    const int nc = guide.channels;
    std::vector<int> xp, yp, xq, yq;
    clampedIndices(tile.x0 - F, pw, guide.width, xp);
    clampedIndices(tile.y0 - F, ph, guide.height, yp);
    int o = 0;
    for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx, ++o) {
            clampedIndices(tile.x0 - F + dx, pw, guide.width, xq);
            clampedIndices(tile.y0 - F + dy, ph, guide.height, yq);
            // Away from the image's left and right edges both runs of pixels are contiguous.
            const bool contiguous =
                xp.front() + pw - 1 == xp.back() && xq.front() + pw - 1 == xq.back();
            for (int y = 0; y < ph; ++y) {
                const size_t rowP = size_t(yp[size_t(y)]) * size_t(guide.width);
                const size_t rowQ = size_t(yq[size_t(y)]) * size_t(guide.width);
                float* d = &distance_[size_t(y) * pw];
                if (contiguous) {
                    const size_t p0 = (rowP + size_t(xp.front())) * size_t(nc);
                    const size_t q0 = (rowQ + size_t(xq.front())) * size_t(nc);
                    const float *gp = &guide.values[p0], *gq = &guide.values[q0];
                    const float *vp = &variance.values[p0], *vq = &variance.values[q0];
                    for (int x = 0; x < pw; ++x, gp += nc, gq += nc, vp += nc, vq += nc)
                        d[x] = pixelDistance(gp, gq, vp, vq, nc, k2, params.varianceScale);
                    continue;
                }
                for (int x = 0; x < pw; ++x) {
                    size_t p = (rowP + size_t(xp[size_t(x)])) * size_t(nc);
                    size_t q = (rowQ + size_t(xq[size_t(x)])) * size_t(nc);
                    d[x] = pixelDistance(&guide.values[p], &guide.values[q], &variance.values[p],
                                         &variance.values[q], nc, k2, params.varianceScale);
                }
            }
            patchSums(tw, th, pw, ph, F);
            float* out = &weights_[size_t(o) * pixels_];
            for (int y = 0; y < th; ++y)
                for (int x = 0; x < tw; ++x) {
                    int qx = tile.x0 + x + dx, qy = tile.y0 + y + dy;
                    if (qx < 0 || qy < 0 || qx >= guide.width || qy >= guide.height) continue;
                    float sum = patch_[size_t(y) * tw + x];
                    out[size_t(y) * tw + x] = std::exp(-std::max(sum * norm, 0.0f));
                }
        }
}

Image nlMeans(const Image& image, const Image& guide, const Image& variance,
              const NlMeansParams& params) {
    const int nc = image.channels, R = params.windowRadius;
    Image out(image.width, image.height, nc);
    const std::vector<Rect> tiles = tilesOf(image.width, image.height, kTile);
    tbb::enumerable_thread_specific<TileWeights> scratch;
    tbb::parallel_for(size_t(0), tiles.size(), [&](size_t t) {
        const Rect& tile = tiles[t];
        TileWeights& weights = scratch.local();
        weights.compute(guide, variance, tile, params);
        const int tw = tile.width();
        std::vector<double> sum(static_cast<size_t>(nc));
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                std::fill(sum.begin(), sum.end(), 0.0);
                double total = 0;
                size_t local = size_t(y - tile.y0) * tw + size_t(x - tile.x0);
                int o = 0;
                for (int dy = -R; dy <= R; ++dy)
                    for (int dx = -R; dx <= R; ++dx, ++o) {
                        float wq = weights.offset(o)[local];
                        if (wq <= 0) continue;
                        const float* q = image.at(x + dx, y + dy);
                        for (int c = 0; c < nc; ++c) sum[size_t(c)] += double(wq) * q[c];
                        total += wq;
                    }
                // The centre's own weight is 1: total >= 1.
                float* px = out.at(x, y);
                for (int c = 0; c < nc; ++c) px[c] = float(sum[size_t(c)] / total);
            }
    });
    return out;
}

}  // namespace kiln::denoise
