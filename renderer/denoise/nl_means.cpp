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

// Adds channel c's term of the per-pixel distance between the guide values gp and gq (their
// variances vp and vq, already scaled) to d, for n pixels in a row: planar rows, so the loop is
// one stream the compiler vectorises.
inline void addChannelDistance(const float* gp, const float* gq, const float* vp, const float* vq,
                               int n, float k2, float* d) {
    for (int x = 0; x < n; ++x) {
        const float a = vp[x], b = vq[x], diff = gp[x] - gq[x];
        d[x] += (diff * diff - (a + std::min(a, b))) / (k2 * (a + b) + kEpsilon);
    }
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

// The guide and its scaled variance around the tile (F + R beyond it on each side), planar per
// channel, coordinates clamped to the image as the patches read them.
void TileWeights::copyRegion(const Image& guide, const Image& variance, const Rect& tile,
                             int margin, float varianceScale) {
    const int nc = guide.channels;
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
                    addChannelDistance(g + p, g + q, v + p, v + q, pw, k2, d);
                }
                for (int x = 0; x < pw; ++x) d[x] = std::min(d[x] / float(nc), kDistanceClamp);
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
