// The samplers: the independent one unchanged (images stay as they were), the Sobol one uniform in
// every dimension, a (0,m,2)-net in every pair over any aligned power-of-two block of samples,
// decorrelated across pairs and pixels, unbiased, and converging faster on smooth integrands.
#include <array>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "chi2.h"
#include "renderer/accel/accelerator.h"
#include "renderer/core/sampler.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// Values of pair `pair` (dimensions 2 pair + 1, 2 pair + 2) for samples [first, first + n).
std::vector<Sampler::Point2> pairValues(uint64_t pixel, int pair, uint32_t first, uint32_t n) {
    std::vector<Sampler::Point2> out;
    for (uint32_t i = first; i < first + n; ++i) {
        Sampler s(42, pixel, i, SamplerKind::Sobol);
        for (int d = 0; d < 2 * pair; ++d) s.next1D();
        float x = s.next1D(), y = s.next1D();
        out.push_back({x, y});
    }
    return out;
}

// Every elementary interval of area 2^t / n (n = 2^m points) holds exactly 2^t points, for all
// m - t + 1 shapes of 2^k x 2^(m-t-k) cells: the (t,m,2)-net property.
void expectNet(const std::vector<Sampler::Point2>& pts, const std::string& what, int t = 0) {
    const uint32_t n = uint32_t(pts.size());
    const int m = std::countr_zero(n), cellBits = m - t;
    ASSERT_EQ(n, 1u << m);
    for (int k = 0; k <= cellBits; ++k) {
        std::vector<int> cells(size_t(1) << cellBits, 0);
        for (auto [x, y] : pts)
            ++cells[(uint32_t(y * float(1u << (cellBits - k))) << k) |
                    uint32_t(x * float(1u << k))];
        for (int c : cells) ASSERT_EQ(c, 1 << t) << what << " shape " << k;
    }
}

// Pearson's r of (x, y) pairs, from running sums.
struct Correlation {
    double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    void add(double x, double y) {
        n += 1, sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
    }
    double r() const {
        const double cov = sxy / n - sx / n * sy / n;
        return cov / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
    }
};

TEST(Sampler, IndependentValuesAreThoseOfEarlierReleases) {
    // The counter-based formula images were rendered with: key from (seed, pixel, sample), value
    // from key and dimension. Changing it would change every image.
    for (uint64_t pixel : {0ull, 7ull, 123456ull})
        for (uint64_t sample : {0ull, 1ull, 999ull}) {
            Sampler s(5, pixel, sample);
            uint64_t key = mix64(mix64(mix64(5) ^ pixel) ^ sample);
            for (uint32_t d = 1; d <= 6; ++d) {
                uint64_t bits = mix64(key + 0x9e3779b97f4a7c15ull * d);
                ASSERT_EQ(s.next1D(), float(bits >> 40) * 0x1.0p-24f);
            }
        }
}

TEST(Sampler, SobolPairsAreNetsOverEveryAlignedPowerOfTwoBlock) {
    // In a (0,m,2)-net every elementary interval of area 2^-m holds exactly one point: check all
    // m + 1 shapes of 2^k x 2^(m-k) cells, for prefixes and for later aligned blocks (a resumed or
    // sharded render continues the sequence).
    for (uint64_t pixel : {0ull, 31ull, 7777ull})
        for (int pair = 0; pair < 6; ++pair)
            for (int m = 1; m <= 9; ++m)
                for (uint32_t block : {0u, 1u, 5u}) {
                    uint32_t n = 1u << m;
                    expectNet(pairValues(pixel, pair, block * n, n),
                              "pixel " + std::to_string(pixel) + " pair " + std::to_string(pair) +
                                  " m " + std::to_string(m) + " block " + std::to_string(block));
                }
}

TEST(Sampler, Next2DIsANetWhateverCameBeforeAndIndependentIsUnchanged) {
    // A 2D sample after an odd number of 1D draws (a light choice, a lobe choice) still comes from
    // one pair: 2^m samples of it form a (0,m,2)-net. The independent sampler's next2D is two
    // next1D values, so its images do not change.
    for (int before : {0, 1, 4, 5}) {
        constexpr int m = 6;
        constexpr uint32_t n = 1u << m;
        std::vector<Sampler::Point2> pts;
        for (uint32_t i = 0; i < n; ++i) {
            Sampler s(11, 99, i, SamplerKind::Sobol);
            for (int k = 0; k < before; ++k) s.next1D();
            pts.push_back(s.next2D());
            Sampler a(11, 99, i), b(11, 99, i);
            for (int k = 0; k < before; ++k) a.next1D(), b.next1D();
            auto [x, y] = a.next2D();
            float bx = b.next1D(), by = b.next1D();
            ASSERT_EQ(x, bx);
            ASSERT_EQ(y, by);
        }
        expectNet(pts, "after " + std::to_string(before));
    }
}

TEST(Sampler, SkippedDimensionsLeaveEveryLaterValueUnchanged) {
    // skip1D / skip2D consume dimensions without computing them (the one light's choice, a
    // pinhole's lens): every value drawn after them equals the value a full draw would give, for
    // either sampler and any pattern of skips.
    const std::vector<std::vector<int>> patterns = {
        {0, 1, 0, 0}, {1, 1, 0, 2}, {2, 0, 1, 1, 0}, {1, 2, 1, 0, 1}, {2, 2, 1}};
    for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent})
        for (uint32_t i : {0u, 1u, 37u, 1000u})
            for (const auto& pattern : patterns) {
                Sampler full(3, 55, i, kind), skipping(3, 55, i, kind);
                for (int step : pattern) {  // 0: next1D, 1: skip1D, 2: skip2D (then compare)
                    if (step == 0) {
                        ASSERT_EQ(skipping.next1D(), full.next1D());
                    } else if (step == 1) {
                        skipping.skip1D(), full.next1D();
                    } else {
                        skipping.skip2D(), full.next2D();
                    }
                    ASSERT_EQ(skipping.dimension(), full.dimension());
                    auto [a, b] = full.next2D();
                    auto [c, d] = skipping.next2D();
                    ASSERT_EQ(a, c);
                    ASSERT_EQ(b, d);
                }
            }
}

TEST(Sampler, SplitDrawsAreNetsWithinAVertexAndAcrossAPixel) {
    // A vertex's count split draws are one aligned block of the pair's sequence: a (0,m,2)-net by
    // themselves, and with the same vertex's draws of the pixel's other samples one net of
    // count x samples points. The split reserves its pairs as that many next2D calls would.
    for (uint32_t count : {2u, 4u, 8u})
        for (int before : {0, 1, 3}) {
            constexpr uint32_t kSamples = 16;
            std::vector<Sampler::Point2> pixel;
            for (uint32_t i = 0; i < kSamples; ++i) {
                Sampler s(21, 7, i, SamplerKind::Sobol), plain(21, 7, i, SamplerKind::Sobol);
                for (int k = 0; k < before; ++k) s.next1D(), plain.next1D();
                const Sampler::Split split = s.split(2, count);
                plain.next2D(), plain.next2D();
                ASSERT_EQ(s.dimension(), plain.dimension());
                ASSERT_EQ(s.next1D(), plain.next1D());  // later draws as after the two next2D
                for (uint32_t pairOffset : {0u, 1u}) {
                    std::vector<Sampler::Point2> vertex;
                    for (uint32_t k = 0; k < count; ++k)
                        vertex.push_back(s.splitDraw(split, pairOffset, k));
                    expectNet(vertex, "vertex of sample " + std::to_string(i) + " count " +
                                          std::to_string(count));
                    if (pairOffset == 0) pixel.insert(pixel.end(), vertex.begin(), vertex.end());
                }
            }
            expectNet(pixel, "pixel, count " + std::to_string(count));
        }
}

TEST(Sampler, SplitDrawsAreUniformAndIndependentOfEachOther) {
    // Across pixels (independent scrambles) each draw k of a split is uniform on the square, for
    // both samplers: chi-square over 8 x 8 cells, and draw k and draw k + 1 of the independent
    // sampler are uncorrelated (|r| within 5 standard errors).
    constexpr int kCells = 64, kPixels = 64 * 200;
    for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent})
        for (uint32_t k : {0u, 1u, 3u}) {
            std::vector<double> counts(kCells, 0.0);
            Correlation c;
            for (int p = 0; p < kPixels; ++p) {
                Sampler s(4, uint64_t(p), 5, kind);
                s.next1D();
                const Sampler::Split split = s.split(1, 4);
                auto [x, y] = s.splitDraw(split, 0, k);
                ASSERT_TRUE(x >= 0 && x < 1 && y >= 0 && y < 1);
                counts[size_t(y * 8) * 8 + size_t(x * 8)] += 1;
                c.add(x, s.splitDraw(split, 0, (k + 1) % 4).u);
            }
            const test::Chi2Result chi2 =
                test::chi2FromCounts(counts, std::vector<double>(kCells, double(kPixels) / kCells));
            EXPECT_GT(chi2.pValue, 1e-4 / 6) << "draw " << k << ": " << chi2.table;
            if (kind == SamplerKind::Independent) {
                EXPECT_LT(std::abs(c.r()), 5 / std::sqrt(c.n)) << "draw " << k;
            }
        }
}

TEST(Sampler, SobolEveryDimensionIsUniform) {
    // One sample per pixel across many pixels: the scrambles are independent per pixel, so the
    // values are iid uniform; chi-square over 64 bins for each of the first 8 dimensions.
    constexpr int kBins = 64, kPixels = 64 * 200;
    for (int d = 0; d < 8; ++d) {
        for (uint32_t sample : {0u, 3u}) {
            std::vector<double> counts(kBins, 0.0), expected(kBins, double(kPixels) / kBins);
            for (int p = 0; p < kPixels; ++p) {
                Sampler s(9, uint64_t(p), sample, SamplerKind::Sobol);
                float v = 0;
                for (int k = 0; k <= d; ++k) v = s.next1D();
                ASSERT_GE(v, 0.0f);
                ASSERT_LT(v, 1.0f);
                counts[size_t(v * kBins)] += 1;
            }
            double chi2 = 0;
            for (int b = 0; b < kBins; ++b)
                chi2 += (counts[b] - expected[b]) * (counts[b] - expected[b]) / expected[b];
            // Significance 1e-4 after a Bonferroni factor for the 16 histograms.
            EXPECT_GT(test::gammaQ((kBins - 1) / 2.0, chi2 / 2.0), 1e-4 / 16)
                << "dimension " << d << " sample " << sample << " chi2 " << chi2;
        }
    }
}

TEST(Sampler, SobolPairsAndPixelsAreDecorrelated) {
    // Correlation of dimension 1 with dimensions 2..8 over 16 samples of 1024 pixels: |r| stays
    // within 5 standard errors (1 / sqrt(N)) of zero. Within a pair the net makes r exactly small
    // too; across pairs only the seeds decorrelate.
    constexpr int kPixels = 1024, kSamples = 16, kDims = 8;
    for (int d = 1; d < kDims; ++d) {
        Correlation c;
        for (int p = 0; p < kPixels; ++p)
            for (uint32_t i = 0; i < kSamples; ++i) {
                Sampler s(3, uint64_t(p), i, SamplerKind::Sobol);
                double x = s.next1D(), y = 0;
                for (int k = 1; k <= d; ++k) y = s.next1D();
                c.add(x, y);
            }
        EXPECT_LT(std::abs(c.r()), 5.0 / std::sqrt(c.n)) << "dimension 1 against " << d + 1;
    }
}

TEST(Sampler, SobolDirectionsAreJoeAndKuos) {
    // Dimensions 2 and 3 (degrees 2 and 3) from Joe and Kuo's new-joe-kuo-6.21201, whose first
    // generator columns Burley's and pbrt-v4's Sobol tables list.
    const uint32_t dim2[] = {0x80000000u, 0xc0000000u, 0x60000000u, 0x90000000u,
                             0xe8000000u, 0x5c000000u, 0x8e000000u, 0xc5000000u};
    const uint32_t dim3[] = {0x80000000u, 0xc0000000u, 0x20000000u, 0x50000000u,
                             0xf8000000u, 0x74000000u, 0xa2000000u, 0x93000000u};
    for (int bit = 0; bit < 8; ++bit) {
        EXPECT_EQ(sobolDirection(2, bit), dim2[bit]) << "bit " << bit;
        EXPECT_EQ(sobolDirection(3, bit), dim3[bit]) << "bit " << bit;
        // Dimension 1: v_0 = 2^31, v_k = v_{k-1} ^ v_{k-1} >> 1.
        const uint32_t before = bit == 0 ? 0 : sobolDirection(1, bit - 1);
        EXPECT_EQ(sobolDirection(1, bit), bit == 0 ? 0x80000000u : before ^ (before >> 1));
    }
}

// The bounce samples of four path vertices for samples [first, first + n) of a pixel, drawn
// between the numbers a path draws there (a light's choice and point, the lobe choice, the
// roulette); independent2D: next2D instead of nextBounce2D.
std::vector<std::array<Sampler::Point2, 4>> bounceValues(uint64_t pixel, uint32_t first, uint32_t n,
                                                         bool independent2D = false) {
    std::vector<std::array<Sampler::Point2, 4>> out;
    for (uint32_t i = first; i < first + n; ++i) {
        Sampler s(42, pixel, i, SamplerKind::Sobol);
        s.next2D(), s.skip2D();  // the pixel position, the lens
        std::array<Sampler::Point2, 4> b;
        for (auto& v : b) {
            s.skip1D(), s.next2D(), s.skip1D();  // the light's choice and point, the lobe
            v = independent2D ? s.next2D() : s.nextBounce2D();
            s.next1D();  // the roulette
        }
        out.push_back(b);
    }
    return out;
}

// Whether every one of the 16 boxes [0, 1/2) or [1/2, 1) along each of four coordinates holds
// exactly n / 16 of the points (a, b) joined.
bool fillsEvery4DBox(const std::vector<std::array<Sampler::Point2, 4>>& v, int a, int b) {
    std::vector<size_t> boxes(16, 0);
    for (const auto& p : v)
        ++boxes[size_t(p[a].u >= 0.5f) | size_t(p[a].v >= 0.5f) << 1 | size_t(p[b].u >= 0.5f) << 2 |
                size_t(p[b].v >= 0.5f) << 3];
    for (size_t c : boxes)
        if (c != v.size() / 16) return false;
    return true;
}

TEST(Sampler, TwoVerticesBounceDirectionsAreOne4DNet) {
    // Bounces 1 and 2 (and 3 and 4) are the halves of one 4D Sobol point: over any aligned block of
    // 2^m >= 16 samples each of the 16 half-boxes of [0,1)^4 holds 2^m / 16. The first half is a
    // (0,m,2)-net, the second (Sobol dimensions 2 and 3) a (1,m,2)-net. Two next2D pairs, shuffled
    // apart, are no 4D net: the check fails on them.
    int pairsFailing = 0;
    for (uint64_t pixel : {0ull, 31ull, 7777ull})
        for (int m = 4; m <= 9; ++m)
            for (uint32_t block : {0u, 3u}) {
                const uint32_t n = 1u << m;
                const auto v = bounceValues(pixel, block * n, n);
                const std::string what = "pixel " + std::to_string(pixel) + " m " +
                                         std::to_string(m) + " block " + std::to_string(block);
                EXPECT_TRUE(fillsEvery4DBox(v, 0, 1)) << what;
                EXPECT_TRUE(fillsEvery4DBox(v, 2, 3)) << what;
                for (int k = 0; k < 4; ++k) {
                    std::vector<Sampler::Point2> half;
                    for (const auto& p : v) half.push_back(p[size_t(k)]);
                    expectNet(half, what + " bounce " + std::to_string(k + 1), k % 2);
                }
                pairsFailing += !fillsEvery4DBox(bounceValues(pixel, block * n, n, true), 0, 1);
            }
    EXPECT_GT(pairsFailing, 0);
}

TEST(Sampler, BounceSamplesAreUniformAndIndependentOfEachOther) {
    // One sample per pixel across many pixels: each coordinate of bounces 1-3 is uniform
    // (chi-square over 64 bins), and the first bounce's u is uncorrelated with every other
    // coordinate (|r| within 5 standard errors), within its 4D point and beyond it.
    constexpr int kBins = 64, kPixels = 64 * 200;
    std::vector<std::vector<double>> counts(6, std::vector<double>(kBins, 0.0));
    std::vector<Correlation> corr(5);
    for (int p = 0; p < kPixels; ++p) {
        const auto v = bounceValues(uint64_t(p), 5, 1)[0];
        const float c[6] = {v[0].u, v[0].v, v[1].u, v[1].v, v[2].u, v[2].v};
        for (int k = 0; k < 6; ++k) {
            ASSERT_GE(c[k], 0.0f);
            ASSERT_LT(c[k], 1.0f);
            counts[size_t(k)][size_t(c[k] * kBins)] += 1;
            if (k > 0) corr[size_t(k - 1)].add(c[0], c[k]);
        }
    }
    const double expected = double(kPixels) / kBins;
    for (int k = 0; k < 6; ++k) {
        double chi2 = 0;
        for (double c : counts[size_t(k)]) chi2 += (c - expected) * (c - expected) / expected;
        // Significance 1e-4 after a Bonferroni factor for the 6 histograms.
        EXPECT_GT(test::gammaQ((kBins - 1) / 2.0, chi2 / 2.0), 1e-4 / 6)
            << "coordinate " << k << " chi2 " << chi2;
    }
    for (int k = 0; k < 5; ++k)
        EXPECT_LT(std::abs(corr[size_t(k)].r()), 5.0 / std::sqrt(corr[size_t(k)].n))
            << "coordinate 0 against " << k + 1;
}

// f(x, y) = exp(x) sin(pi y) on [0,1]^2, integral (e - 1) 2 / pi.
double smooth(double x, double y) { return std::exp(x) * std::sin(kPi * y); }
const double kSmoothIntegral = (std::exp(1.0) - 1.0) * 2.0 / kPi;

// Per-pixel estimates of the smooth integral with n samples of pair 1 (dimensions 3, 4).
std::vector<double> estimates(SamplerKind kind, int pixels, uint32_t n) {
    std::vector<double> out;
    for (int p = 0; p < pixels; ++p) {
        double sum = 0;
        for (uint32_t i = 0; i < n; ++i) {
            Sampler s(17, uint64_t(p), i, kind);
            s.next1D(), s.next1D();
            double x = s.next1D(), y = s.next1D();
            sum += smooth(x, y);
        }
        out.push_back(sum / n);
    }
    return out;
}

TEST(Sampler, SobolIsUnbiasedAndConvergesFasterOnSmoothIntegrands) {
    constexpr int kPixels = 400;
    for (uint32_t n : {1u, 16u, 256u}) {
        std::vector<double> e = estimates(SamplerKind::Sobol, kPixels, n);
        double mean = 0, var = 0;
        for (double v : e) mean += v / kPixels;
        for (double v : e) var += (v - mean) * (v - mean) / (kPixels - 1);
        // The pixels' scrambles are independent: the mean of their estimates is within 4 standard
        // errors of the integral (with a floor for float quantisation of the sample values).
        double tolerance = 4.0 * std::sqrt(var / kPixels) + 1e-6;
        EXPECT_NEAR(mean, kSmoothIntegral, tolerance) << n << " spp";
    }
    // Owen-scrambled nets converge as n^-3/2 in RMSE on smooth integrands, independent samples as
    // n^-1/2: at 256 spp the gap is more than 10x (about 16x in expectation).
    auto rmse = [&](SamplerKind kind) {
        double sq = 0;
        for (double v : estimates(kind, 200, 256))
            sq += (v - kSmoothIntegral) * (v - kSmoothIntegral) / 200;
        return std::sqrt(sq);
    };
    EXPECT_LT(rmse(SamplerKind::Sobol) * 10, rmse(SamplerKind::Independent));
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

RenderJobOptions sobolJob(int threads, int tile) {
    RenderJobOptions o = test::jobOptions(40, 30, 16, PathOptions{}, AovRequest::defaults());
    o.settings.sampler = SamplerKind::Sobol;
    o.settings.threads = threads, o.settings.tileSize = tile;
    return o;
}

TEST(SobolRender, IsBitIdenticalForAnyThreadCountAndTileSize) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    Film a = test::renderJob(s, *accel, sobolJob(2, 32)),
         b = test::renderJob(s, *accel, sobolJob(1, 7));
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            ASSERT_EQ(a.pixel(x, y), b.pixel(x, y)) << x << "," << y;
            for (size_t c = 0; c < a.layout().channels().size(); ++c)
                ASSERT_EQ(a.aov(x, y, c), b.aov(x, y, c));
        }
}

TEST(SobolRender, MeanAgreesWithTheIndependentSampler) {
    // Both estimators are unbiased: their image means differ by less than 4 standard errors of the
    // difference, estimated from the per-pixel variances of each render.
    Scene s = loadScene(test::cs184("sky/CBbunny.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = test::jobOptions(32, 24, 64, PathOptions{}, AovRequest::defaults());
    double mean[2] = {0, 0}, var[2] = {0, 0};
    const double n = 32.0 * 24.0;
    for (int k = 0; k < 2; ++k) {
        o.settings.sampler = k ? SamplerKind::Sobol : SamplerKind::Independent;
        Film f = test::renderJob(s, *accel, o);
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 32; ++x) {
                mean[k] += luminance(f.pixel(x, y)) / n;
                var[k] += f.luminanceVariance(x, y) / (n * n);
            }
    }
    EXPECT_NEAR(mean[0], mean[1], 4.0 * std::sqrt(var[0] + var[1]));
}

}  // namespace
}  // namespace kiln
