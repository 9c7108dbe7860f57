#include "renderer/denoise/regression.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "renderer/denoise/avx2_clone.h"

namespace kiln::denoise {
namespace {

constexpr int kMaxColumns = 16;
// Ridge on the normalised system's slope columns: nearly collinear features stay solvable; the
// intercept is never shrunk (a constant image stays constant).
constexpr double kRidge = 1e-3;
// A column whose weighted energy is this small beside the intercept's carries nothing.
constexpr double kNegligibleColumn = 1e-12;

// Solves A x = b (3 right-hand sides) for the symmetric positive definite A by Cholesky, in place.
void solveCholesky(double (*A)[kMaxColumns], double (*b)[3], int n) {
    for (int j = 0; j < n; ++j) {
        double d = A[j][j];
        for (int k = 0; k < j; ++k) d -= A[j][k] * A[j][k];
        d = std::sqrt(std::max(d, 1e-300));
        A[j][j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = A[i][j];
            for (int k = 0; k < j; ++k) s -= A[i][k] * A[j][k];
            A[i][j] = s / d;
        }
    }
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < n; ++i) {
            double s = b[i][c];
            for (int k = 0; k < i; ++k) s -= A[i][k] * b[k][c];
            b[i][c] = s / A[i][i];
        }
        for (int i = n - 1; i >= 0; --i) {
            double s = b[i][c];
            for (int k = i + 1; k < n; ++k) s -= A[k][i] * b[k][c];
            b[i][c] = s / A[i][i];
        }
    }
}

// Regression coefficients: N regressors x RGB.
template <int N>
using Coefficients = std::array<std::array<double, 3>, size_t(N)>;

// The window of one pixel's fit: its neighbours with a weight, their regressors
// [1, dx / R, dy / R, feature - feature(p)] (N columns, zero-padded) and colours.
template <int N>
struct Window {
    int rows = 0;
    std::vector<std::array<double, size_t(N)>> x;
    std::vector<std::array<float, 3>> y;
    std::vector<float> w;
    std::vector<int> at;  // the neighbour's pixel index
};

template <int N, typename WeightAt>
void gatherWindow(const Image& colour, const Image& features, int px, int py, int R,
                  WeightAt weightAt, Window<N>& win) {
    const size_t most = size_t(2 * R + 1) * size_t(2 * R + 1);
    win.x.resize(most), win.y.resize(most), win.w.resize(most), win.at.resize(most);
    win.rows = 0;
    const float* fp = features.at(px, py);
    const int nf = features.channels;
    for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
            float w = weightAt(dx, dy);
            if (w <= 0) continue;
            const int k = win.rows++;
            std::array<double, size_t(N)>& x = win.x[size_t(k)];
            x.fill(0.0);
            x[0] = 1.0, x[1] = double(dx) / R, x[2] = double(dy) / R;
            const float* fq = features.at(px + dx, py + dy);
            for (int c = 0; c < nf; ++c) x[size_t(3 + c)] = double(fq[c]) - double(fp[c]);
            const float* y = colour.at(px + dx, py + dy);
            win.y[size_t(k)] = {y[0], y[1], y[2]};
            win.w[size_t(k)] = w;
            win.at[size_t(k)] = (py + dy) * colour.width + px + dx;
        }
}

// The weighted least-squares coefficients (N x RGB) of the window.
template <int N>
KILN_AVX2_CLONE Coefficients<N> fitWindow(const Window<N>& win) {
    if (win.rows == 1) {  // the centre alone (no neighbour like it): the plane is its colour
        Coefficients<N> beta{};
        for (int c = 0; c < 3; ++c) beta[0][size_t(c)] = win.y[0][size_t(c)];
        return beta;
    }
    double A[N][N] = {}, b[N][3] = {};
    for (int k = 0; k < win.rows; ++k) {
        const std::array<double, size_t(N)>& x = win.x[size_t(k)];
        const double w = win.w[size_t(k)];
        for (int i = 0; i < N; ++i) {
            const double wx = w * x[size_t(i)];
            for (int j = 0; j <= i; ++j) A[i][j] += wx * x[size_t(j)];  // the lower triangle
            for (int c = 0; c < 3; ++c) b[i][c] += wx * win.y[size_t(k)][size_t(c)];
        }
    }
    // Normalised (unit diagonal), negligible columns dropped, ridge on the slopes.
    int keep[kMaxColumns] = {}, m = 0;
    for (int i = 0; i < N; ++i)
        if (i == 0 || A[i][i] > kNegligibleColumn * A[0][0]) keep[m++] = i;
    double S[kMaxColumns][kMaxColumns] = {}, r[kMaxColumns][3] = {}, scale[kMaxColumns] = {};
    for (int a = 0; a < m; ++a) scale[a] = 1.0 / std::sqrt(A[keep[a]][keep[a]]);
    for (int a = 0; a < m; ++a) {
        for (int c = 0; c < 3; ++c) r[a][c] = b[keep[a]][c] * scale[a];
        for (int e = 0; e <= a; ++e) S[a][e] = A[keep[a]][keep[e]] * scale[a] * scale[e];
        if (a > 0) S[a][a] += kRidge;
    }
    solveCholesky(S, r, m);
    Coefficients<N> beta{};
    for (int a = 0; a < m; ++a)
        for (int c = 0; c < 3; ++c) beta[size_t(keep[a])][size_t(c)] = r[a][c] * scale[a];
    return beta;
}

// Each neighbour's fitted colour, weighted, into sum (RGB, weight per pixel).
template <int N>
KILN_AVX2_CLONE void spreadFit(const Window<N>& win, const Coefficients<N>& beta, Image& sum) {
    for (int k = 0; k < win.rows; ++k) {
        const std::array<double, size_t(N)>& x = win.x[size_t(k)];
        double v[3] = {0, 0, 0};
        for (int j = 0; j < N; ++j)
            for (int c = 0; c < 3; ++c) v[c] += beta[size_t(j)][size_t(c)] * x[size_t(j)];
        float* s = &sum.values[size_t(win.at[size_t(k)]) * 4];
        const float w = win.w[size_t(k)];
        for (int c = 0; c < 3; ++c) s[c] += w * float(v[c]);
        s[3] += w;
    }
}

constexpr int kMinTile = 32;

// The classes of tiles: tiles of one class lie two tiles apart, so their windows (R beyond the
// tile) never meet and they can add into the sums in parallel.
std::vector<std::vector<size_t>> tileClasses(size_t tiles, int tilesX) {
    std::vector<std::vector<size_t>> classes(4);
    for (size_t t = 0; t < tiles; ++t)
        classes[size_t(int(t % size_t(tilesX)) % 2 + 2 * (int(t / size_t(tilesX)) % 2))].push_back(
            t);
    return classes;
}

// Below this weight of the grid's fits (as the pixel's own weights estimate it) a pixel gets a
// fit of its own: the grid's planes, evaluated away from their centres, would extrapolate there.
constexpr float kMinCoverage = 1.0f;

// Whether the pixel is a fit centre: on the grid of every stride-th pixel, or too little like the
// grid's centres around it.
template <typename WeightAt>
bool isCentre(int px, int py, int R, int stride, WeightAt weightAt) {
    if (px % stride == 0 && py % stride == 0) return true;
    float coverage = 0;
    for (int dy = -R + (stride - (py - R) % stride) % stride; dy <= R; dy += stride)
        for (int dx = -R + (stride - (px - R) % stride) % stride; dx <= R; dx += stride)
            coverage += weightAt(dx, dy);
    return coverage < kMinCoverage;
}

// Each sum's weighted fits over its weight; a pixel no fit reached keeps its colour.
Image fitsOverWeights(const Image& sum, const Image& colour) {
    Image out(sum.width, sum.height, 3);
    for (size_t p = 0; p < out.pixels(); ++p)
        for (int c = 0; c < 3; ++c) {
            const float weight = sum.values[p * 4 + 3];
            out.values[p * 3 + c] =
                weight > 0 ? sum.values[p * 4 + c] / weight : colour.values[p * 3 + c];
        }
    return out;
}

// N: the regressors, 3 + features, zero-padded to a size the loops unroll for.
template <int N>
std::vector<Image> regress(const Image& colour, const Image& guide, const Image& features,
                           const Image& variance, const RegressionParams& params) {
    const int w = colour.width, h = colour.height, R = params.weights.windowRadius;
    const int stride = params.fitStride;
    const int tileSize = std::max(kMinTile, 2 * R);
    const std::vector<Rect> tiles = tilesOf(w, h, tileSize);
    std::vector<Image> sums(params.bandwidths.size(), Image(w, h, 4));  // weighted fits, weights
    tbb::enumerable_thread_specific<TileWeights> scratch;
    tbb::enumerable_thread_specific<Window<N>> windows;
    for (const std::vector<size_t>& ofClass :
         tileClasses(tiles.size(), (w + tileSize - 1) / tileSize))
        tbb::parallel_for(size_t(0), ofClass.size(), [&](size_t i) {
            const Rect& tile = tiles[ofClass[i]];
            TileWeights& weights = scratch.local();
            weights.compute(guide, variance, tile, params.weights);
            Window<N>& win = windows.local();
            for (size_t b = 0; b < sums.size(); ++b) {
                weights.weigh(params.bandwidths[b]);
                for (int py = tile.y0; py < tile.y1; ++py)
                    for (int px = tile.x0; px < tile.x1; ++px) {
                        size_t local =
                            size_t(py - tile.y0) * size_t(tile.width()) + size_t(px - tile.x0);
                        auto weightAt = [&](int dx, int dy) {
                            return weights.offset((dy + R) * (2 * R + 1) + dx + R)[local];
                        };
                        if (!isCentre(px, py, R, stride, weightAt)) continue;
                        gatherWindow(colour, features, px, py, R, weightAt, win);
                        spreadFit(win, fitWindow(win), sums[b]);
                    }
            }
        });
    std::vector<Image> out;
    for (const Image& sum : sums) out.push_back(fitsOverWeights(sum, colour));
    return out;
}

}  // namespace

std::vector<Image> collaborativeRegression(const Image& colour, const Image& guide,
                                           const Image& features, const Image& variance,
                                           const RegressionParams& params) {
    // The film's seven features (half_buffers.h) take the unrolled path.
    if (features.channels == 7) return regress<10>(colour, guide, features, variance, params);
    return regress<kMaxColumns>(colour, guide, features, variance, params);
}

}  // namespace kiln::denoise
