// Math, bounds, transforms and the counter-based sampler.
#include <algorithm>
#include <cmath>

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

}  // namespace
}  // namespace kiln
