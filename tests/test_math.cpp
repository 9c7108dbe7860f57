// Math, bounds, transforms and the counter-based sampler.
#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/core/angle_table.h"
#include "renderer/core/distribution.h"
#include "renderer/core/math.h"
#include "renderer/core/sampler.h"
#include "renderer/core/warp.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(Mat4, InverseTimesMatrixIsIdentity) {
    Mat4 m;
    double v[16] = {0.6, -1.2e-7, 0, -2.6e-8, 9.06e-8, -0.8, 0, 0.0043, 0, 0, 1, 1.49, 0, 0, 0, 1};
    for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v[i];
    Mat4 p = m * m.inverse();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(p.m[i][j], i == j ? 1.0 : 0.0, 1e-12);
}

TEST(Mat4, NormalsStayPerpendicularUnderNonUniformScale) {
    Mat4 m;
    m.m[0][0] = 4, m.m[1][1] = 0.5, m.m[2][2] = 1;
    Vec3 tangent = normalize(Vec3(1, 1, 0)), normal = normalize(Vec3(1, -1, 0));
    EXPECT_NEAR(dot(m.vector(tangent), m.normal(normal)), 0.0f, 1e-6f);
}

TEST(Bounds, EmptyUnionAndSurfaceArea) {
    Bounds3 b;
    EXPECT_TRUE(b.empty());
    EXPECT_EQ(b.surfaceArea(), 0.0f);
    b.extend(Vec3(0, 0, 0));
    b.extend(Vec3(1, 2, 3));
    EXPECT_FALSE(b.empty());
    EXPECT_FLOAT_EQ(b.surfaceArea(), 2 * (2 + 6 + 3));
    EXPECT_EQ(b.centroid(), Vec3(0.5f, 1, 1.5f));
}

TEST(Sampler, PureFunctionOfSeedPixelSampleDimension) {
    Sampler a(7, 123, 4), b(7, 123, 4), c(7, 123, 5), d(8, 123, 4);
    for (int i = 0; i < 16; ++i) {
        float x = a.next1D();
        EXPECT_EQ(x, b.next1D());
        EXPECT_NE(x, c.next1D());
        EXPECT_NE(x, d.next1D());
    }
}

TEST(Sampler, UniformByChiSquare) {
    // 64 bins, 640,000 draws over many pixels/samples/dimensions. Under uniformity the statistic is
    // chi-square with 63 degrees of freedom; 1e-6 significance corresponds to about 130.
    constexpr int kBins = 64, kDraws = 640000;
    std::vector<int> counts(kBins, 0);
    for (int i = 0; i < kDraws / 8; ++i) {
        Sampler s(1, uint64_t(i % 1000), uint64_t(i / 1000));
        for (int d = 0; d < 8; ++d) {
            float u = s.next1D();
            ASSERT_GE(u, 0.0f);
            ASSERT_LT(u, 1.0f);
            ++counts[int(u * kBins)];
        }
    }
    double expected = double(kDraws) / kBins, chi2 = 0;
    for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 130.0);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

TEST(Warp, QuarterTurnSinCosMatchTheLibraryToAFewUlps) {
    // The concentric map's polynomials: on [-pi/4, pi/4] within 2e-7 of double-precision sin/cos
    // (about 3 ulps at 0.7), and the map keeps the radius: |(x, y)| = max(|2u1 - 1|, |2u2 - 1|).
    for (int i = -1000; i <= 1000; ++i) {
        float t = float(i) / 1000 * (kPi / 4), s, c;
        sinCosQuarterPi(t, s, c);
        ASSERT_NEAR(s, std::sin(double(t)), 2e-7) << t;
        ASSERT_NEAR(c, std::cos(double(t)), 2e-7) << t;
    }
    for (int i = 0; i <= 64; ++i)
        for (int j = 0; j <= 64; ++j) {
            float u1 = float(i) / 64, u2 = float(j) / 64, x, y;
            concentricDisk(u1, u2, x, y);
            float r = std::max(std::abs(2 * u1 - 1), std::abs(2 * u2 - 1));
            ASSERT_NEAR(std::hypot(x, y), r, 4e-7) << u1 << " " << u2;
        }
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

TEST(SpecialFunctions, ErfInvInvertsErf) {
    // Giles' approximation: erf(erfInv(y)) within a few float ulps of y on (-1, 1), odd.
    for (int i = -999; i <= 999; ++i) {
        float y = float(i) / 1000;
        ASSERT_NEAR(std::erf(double(erfInv(y))), y, 2e-6) << y;
        ASSERT_EQ(erfInv(-y), -erfInv(y));
    }
}

// The guide table's walk picks the bin a binary search over the CDF picks, for every u, on
// distributions with zero bins, spikes and long runs of tiny bins: the environment map's sampling
// is the same bit for bit, only cheaper.
TEST(Distribution1D, GuideTablePicksTheBinABinarySearchPicks) {
    std::vector<std::vector<float>> cases = {
        {1, 1, 1, 1}, {0, 0, 5, 0, 0}, {1e6f, 1e-6f, 1e-6f, 1e-6f, 0, 1}, {0, 0, 0}, {3}};
    std::vector<float> spiky(4096, 1e-4f);
    spiky[17] = 1e3f, spiky[2048] = 50, spiky[4095] = 0;
    cases.push_back(spiky);
    std::vector<float> ramp(1000);
    for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = float(i * i % 97);
    cases.push_back(ramp);
    for (const std::vector<float>& f : cases) {
        Distribution1D d(f);
        // The reference: the CDF as the distribution builds it, searched by upper_bound.
        std::vector<float> cdf(f.size() + 1, 0.0f);
        for (size_t i = 0; i < f.size(); ++i) cdf[i + 1] = cdf[i] + std::max(0.0f, f[i]);
        float total = cdf.back();
        if (total <= 0)
            for (size_t i = 0; i < f.size(); ++i)
                cdf[i + 1] = float(i + 1), total = float(f.size());
        for (float& c : cdf) c /= total;
        auto reference = [&](float u) {
            size_t i = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
            i = std::clamp<size_t>(i, 1, f.size()) - 1;
            while (i + 1 < f.size() && cdf[i + 1] - cdf[i] <= 0) ++i;
            return i;
        };
        std::vector<float> us;
        for (int k = 0; k <= 20000; ++k) us.push_back(std::min(float(k) / 20000, 0x1.fffffep-1f));
        for (float c : cdf)  // every bin edge and its float neighbours
            for (float u : {std::nextafter(c, -1.0f), c, std::nextafter(c, 2.0f)})
                if (u >= 0 && u < 1) us.push_back(u);
        for (float u : us) {
            float pmf;
            ASSERT_EQ(d.sampleDiscrete(u, pmf), reference(u)) << "u " << u << " n " << f.size();
        }
    }
}

// Rows in flat arrays draw exactly what a Distribution1D of each row draws (bin, position,
// density), for every u on a fine grid and at every CDF point and its float neighbours, on rows
// with zero runs, spikes, all zero, tiny bins beside large ones and evenly varying weights (bins
// about a bucket wide: a bucket's bottom bin often ends inside it).
TEST(Distribution1DRows, DrawEachRowAsItsDistribution1D) {
    constexpr size_t n = 64;
    std::vector<std::vector<float>> rows(6, std::vector<float>(n, 1.0f));
    for (size_t i = 0; i < n; ++i) {
        rows[0][i] = float(i * i % 7);
        rows[1][i] = i == 9 ? 1e6f : (i % 5 == 0 ? 0.0f : 1e-6f);
        rows[2][i] = 0.0f;
        rows[3][i] = float(i % 3 == 0) * float(i);
        rows[5][i] = 1.0f + 0.5f * float(i * 37 % 11) / 11.0f;
    }
    std::vector<float> flat;
    for (const auto& r : rows) flat.insert(flat.end(), r.begin(), r.end());
    Distribution1DRows all(flat, n, rows.size());
    for (size_t r = 0; r < rows.size(); ++r) {
        Distribution1D one(rows[r]);
        EXPECT_EQ(all.integral(r), one.integral()) << r;
        std::vector<float> us;
        for (int k = 0; k < 20000; ++k) us.push_back(float(k) / 20000);
        float sum = 0;  // the CDF points as Distribution1D computes them, and their neighbours
        std::vector<float> cdf(1, 0.0f);
        for (float x : rows[r]) cdf.push_back(sum += x);
        for (float& c : cdf) c = sum > 0 ? c / sum : 0.5f;
        for (float c : cdf)
            for (float u : {std::nextafter(c, -1.0f), c, std::nextafter(c, 2.0f)})
                if (u >= 0 && u < 1) us.push_back(u);
        for (float u : us) {
            float pdfA, pdfB;
            size_t ia, ib;
            float a = all.sampleContinuous(r, u, pdfA, ia), b = one.sampleContinuous(u, pdfB, ib);
            ASSERT_EQ(ia, ib) << "row " << r << " u " << u;
            ASSERT_EQ(a, b) << "row " << r << " u " << u;
            ASSERT_EQ(pdfA, pdfB) << "row " << r << " u " << u;
            ASSERT_EQ(all.density(r, ia), one.density(ib));
        }
    }
}

// The table's sine and cosine against double precision libm, over the environment map's two
// ranges (one turned): within 2.5e-7, about two float ulps of 1.
TEST(AngleTable, MatchesLibmToFloatPrecision) {
    const double pi = 3.14159265358979323846;
    struct Range {
        double start, span;
        int steps;
    };
    for (Range r : {Range{0.0, pi, 128}, Range{-pi - 1.3, 2 * pi, 256}}) {
        AngleTable table(r.start, r.span, r.steps);
        double worst = 0;
        for (int k = 0; k <= 100000; ++k) {
            float t = std::min(float(k) / 100000, 0x1.fffffep-1f), s, c;
            table.sinCos(t, s, c);
            double a = r.start + r.span * double(t);
            worst = std::max({worst, std::abs(s - std::sin(a)), std::abs(c - std::cos(a))});
        }
        EXPECT_LT(worst, 2.5e-7) << r.start;
    }
}

// A direction's map coordinates (latLong4, four lanes at once) against double precision atan2 of
// the same float direction, over random directions, the axes and near the poles: within 2.5e-7 of
// a turn (u) and of a half turn (v), the polynomial's documented relative error (Cephes atanf:
// 1.9e-7) of an angle up to pi, over pi (measured: 0.7e-7 and 0.9e-7). And each lane is what
// latLong gives for its direction alone, bit for bit, so a batch of rays finds the coordinates a
// ray finds by itself.
TEST(LatLong, MatchesDoublePrecisionAndLanesAreIndependent) {
    const double pi = 3.14159265358979323846;
    std::vector<Vec3> dirs = {{1, 0, 0},  {-1, 0, 0}, {0, 0, 1},       {0, 0, -1},
                              {0, 1, 0},  {0, -1, 0}, {1e-4f, 1, 0},   {0, -1, 3e-5f},
                              {-1, 0, 1}, {1, 1, 1},  {-0.3f, 0.2f, 0}};
    Sampler rng(7, 0, 0);
    for (int k = 0; k < 200000; ++k) {
        float a = rng.next1D(), b = rng.next1D();
        float z = 1 - 2 * a, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * b;
        dirs.push_back({r * std::cos(phi), z, r * std::sin(phi)});
    }
    double worstU = 0, worstV = 0;
    for (size_t k = 0; k + 4 <= dirs.size(); k += 4) {
        const Vec3* four[4] = {&dirs[k], &dirs[k + 1], &dirs[k + 2], &dirs[k + 3]};
        LatLong found[4];
        latLong4(four, found);
        for (int l = 0; l < 4; ++l) {
            const Vec3& d = dirs[k + size_t(l)];
            const LatLong alone = latLong(d);
            ASSERT_EQ(alone.u, found[l].u) << k + size_t(l);
            ASSERT_EQ(alone.v, found[l].v) << k + size_t(l);
            const double x = d.x, y = d.y, z = d.z;
            const double u = 0.5 + std::atan2(x, -z) / (2 * pi),
                         v = std::atan2(std::sqrt(x * x + z * z), y) / pi;
            // u wraps at the -z axis (atan2 of +-0 there), and is any value at the poles.
            double du = std::abs(found[l].u - u);
            if (x * x + z * z > 0) worstU = std::max(worstU, std::min(du, 1 - du));
            worstV = std::max(worstV, std::abs(found[l].v - v));
        }
    }
    EXPECT_LT(worstU, 2.5e-7);
    EXPECT_LT(worstV, 2.5e-7);
}

}  // namespace
}  // namespace kiln
