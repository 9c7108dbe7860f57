// The accuracy tool's statistics on synthetic images with known answers, and a smoke run of the
// sweep.
#include <fstream>
#include <random>

#include "renderer/validation/accuracy.h"
#include "test_support.h"

namespace kiln {
namespace {

Image flat(int w, int h, float v) {
    Image img;
    img.width = w, img.height = h;
    img.pixels.assign(size_t(w) * h, Color(v));
    return img;
}

TEST(AccuracyStats, KnownErrors) {
    Image ref = flat(4, 3, 0.5f), test = flat(4, 3, 0.6f);
    ErrorStats e = compareImages(test, ref);
    EXPECT_NEAR(e.rmse, 0.1, 1e-6);
    EXPECT_NEAR(e.bias, 0.1, 1e-6);
    EXPECT_NEAR(e.relMse, 0.01 / (0.25 + 0.01), 1e-6);
    EXPECT_EQ(compareImages(ref, ref).rmse, 0.0);
    // A reference with known variance: its share is removed from the squared error.
    ref.variance.assign(ref.pixels.size(), 0.0075);
    EXPECT_NEAR(compareImages(test, ref).rmse, std::sqrt(0.01 - 0.0075), 1e-6);
}

TEST(AccuracyStats, LogLogSlope) {
    std::vector<double> x, y, z;
    for (double s = 1; s <= 1024; s *= 2)
        x.push_back(s), y.push_back(3.0 / s), z.push_back(0.2 / std::sqrt(s));
    EXPECT_NEAR(logLogSlope(x, y), -1.0, 1e-12);
    EXPECT_NEAR(logLogSlope(x, z), -0.5, 1e-12);
    EXPECT_EQ(logLogSlope({1.0}, {1.0}), 0.0);  // one point fits no line
    EXPECT_NEAR(efficiency(0.01, 2.0), 50.0, 1e-9);
}

// A 64x64 checker of 8-pixel cells: albedo 0.2 and 0.8, the image the albedo times 2.
struct Checker {
    Image image;
    std::vector<Color> albedo;
    Checker() : image(flat(64, 64, 0)) {
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const float a = ((x / 8 + y / 8) % 2) ? 0.8f : 0.2f;
                albedo.emplace_back(a);
                image.pixels[size_t(y) * 64 + size_t(x)] = Color(2 * a);
            }
    }
};

TEST(AccuracyStats, AlbedoEdgeContrastFallsWhenEdgesBlur) {
    Checker c;
    EXPECT_NEAR(albedoEdgeContrast(c.image, c.image, c.albedo), 1.0, 1e-12);
    // A horizontal 3-pixel box blur. A step across a vertical edge becomes a third of itself;
    // a step across a horizontal edge stays whole except in the 14 of 64 columns beside a
    // vertical edge (7 edges, a column each side), where the blur mixed both cells: a third.
    // As many pairs cross vertical edges as horizontal ones.
    Image blurred = c.image;
    for (int y = 0; y < 64; ++y)
        for (int x = 1; x < 63; ++x) {
            Color sum(0.0f);
            for (int d = -1; d <= 1; ++d) sum += c.image.pixels[size_t(y) * 64 + size_t(x + d)];
            blurred.pixels[size_t(y) * 64 + size_t(x)] = sum / 3.0f;
        }
    const double horizontal = (50.0 + 14.0 / 3.0) / 64.0, vertical = 1.0 / 3.0;
    EXPECT_NEAR(albedoEdgeContrast(blurred, c.image, c.albedo), (horizontal + vertical) / 2, 1e-5);
    // No albedo edge: nothing to measure.
    EXPECT_LT(albedoEdgeContrast(c.image, c.image, std::vector<Color>(64 * 64, Color(0.5f))), 0);
}

TEST(AccuracyStats, AlbedoEdgeContrastOfANoisyImageIsOneUpToItsNoise) {
    Checker c;
    Image noisy = c.image;
    std::mt19937 rng(5);
    const double sigma = 0.3;
    std::normal_distribution<float> noise(0.0f, float(sigma));
    for (Color& p : noisy.pixels) p += Color(noise(rng));
    // Each edge pair's step gains the difference of two noises (variance 2 sigma^2); a pixel
    // lies in at most two pairs, which at most doubles the variance of their sum.
    const int pairs = 2 * 64 * 7;  // 7 inner edges per row and per column, 64 rows and columns
    const double sharp = pairs * 1.2, sd = std::sqrt(2.0 * 2.0 * sigma * sigma * pairs) / sharp;
    EXPECT_NEAR(albedoEdgeContrast(noisy, c.image, c.albedo), 1.0, 4 * sd);
    EXPECT_GT(sd, 0.0);
}

TEST(AccuracyStats, SvgPlotHasSeriesAndTheSlopeLine) {
    std::string svg = svgLogLogPlot(
        "t", "time", "error", {{"a", {1, 2, 4}, {1, 0.5, 0.25}}, {"b", {1, 10}, {2, 0.2}}}, true);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_NE(svg.find("</svg>"), std::string::npos);
    size_t polylines = 0;
    for (size_t at = svg.find("<polyline"); at != std::string::npos;
         at = svg.find("<polyline", at + 1))
        ++polylines;
    EXPECT_EQ(polylines, 2u);
    EXPECT_NE(svg.find("slope -1"), std::string::npos);
}

// A quick sweep of a CS184 scene at w x h, into the test's scratch directory.
AccuracyOptions quickSweep(const char* scene, int w, int h, int referenceSpp) {
    AccuracyOptions o;
    o.scene = test::cs184(scene);
    o.outDir = (test::scratchDir() / "acc").string();
    o.width = w, o.height = h, o.referenceSpp = referenceSpp, o.quick = true;
    return o;
}

std::string summaryOf(const AccuracyOptions& o) {
    std::ifstream summary(std::filesystem::path(o.outDir) / "summary.md");
    return std::string((std::istreambuf_iterator<char>(summary)), {});
}

TEST(AccuracySweep, QuickRunErrorFallsWithSppAndReusesTheReference) {
    AccuracyOptions o = quickSweep("sky/CBspheres_lambertian.dae", 32, 24, 512);
    AccuracyResult first = runAccuracy(o);
    EXPECT_FALSE(first.referenceCached);
    std::vector<double> spp, rel;
    for (const AccuracyRun& r : first.runs)
        if (r.group == "spp") spp.push_back(r.spp), rel.push_back(r.error.relMse);
    ASSERT_GE(spp.size(), 4u);
    EXPECT_LT(rel.back(), rel.front() / 4);  // 16 spp against 1 spp
    EXPECT_LT(logLogSlope(spp, rel), -0.6);  // about -1
    // The other sampler's sweep converges too (Sobol: at least as fast), and the summary compares.
    std::vector<double> otherSpp, otherRel;
    for (const AccuracyRun& r : first.runs)
        if (r.group == "sampler") {
            EXPECT_NE(r.sampler, first.runs.front().sampler);
            otherSpp.push_back(r.spp), otherRel.push_back(r.error.relMse);
        }
    ASSERT_GE(otherSpp.size(), 2u);
    EXPECT_LT(logLogSlope(otherSpp, otherRel), -0.6);
    std::string text = summaryOf(o);
    EXPECT_NE(text.find("**Sampler**"), std::string::npos) << text;
    for (const char* f : {"accuracy.csv", "error_vs_time.svg", "spp.svg", "summary.md"})
        EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(o.outDir) / f)) << f;
    std::ifstream csv(std::filesystem::path(o.outDir) / "accuracy.csv");
    std::string line;
    int rows = 0;
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, int(first.runs.size()) + 1);
    AccuracyResult second = runAccuracy(o);
    EXPECT_TRUE(second.referenceCached);
}

TEST(AccuracySweep, ComparesGuidedWithUnguidedWhereThePlanGuides) {
    AccuracyOptions o = quickSweep("sky/CBspheres_microfacet_al_ag.dae", 24, 18, 256);
    AccuracyResult r = runAccuracy(o);
    int guided = 0, unguided = 0;
    for (const AccuracyRun& a : r.runs) {
        if (a.group == "spp") guided += a.guided;
        if (a.group == "guiding") unguided += !a.guided;
    }
    EXPECT_GE(guided, 4);
    EXPECT_GE(unguided, 2);
    std::string text = summaryOf(o);
    EXPECT_NE(text.find("**Caustic guiding**"), std::string::npos) << text;
    // The diffuse scene of the test above is not guided: no such sweep there.
    o.scene = test::cs184("sky/CBspheres_lambertian.dae");
    for (const AccuracyRun& a : runAccuracy(o).runs) EXPECT_NE(a.group, "guiding");
}

TEST(AccuracySweep, AovErrorsOnRequest) {
    AccuracyOptions o = quickSweep("sky/CBspheres_lambertian.dae", 24, 18, 256);
    o.aovs = "direct,indirect";
    AccuracyResult r = runAccuracy(o);
    ASSERT_FALSE(r.runs.empty());
    std::vector<double> direct;
    for (const AccuracyRun& a : r.runs) {
        ASSERT_EQ(a.aovErrors.size(), 2u);
        EXPECT_EQ(a.aovErrors[0].first, "direct");
        EXPECT_EQ(a.aovErrors[1].first, "indirect");
        if (a.group == "spp") direct.push_back(a.aovErrors[0].second.relMse);
    }
    EXPECT_LT(direct.back(), direct.front());  // the direct layer converges too
    std::ifstream csv(std::filesystem::path(o.outDir) / "accuracy.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find("rel_mse_direct,rel_mse_indirect"), std::string::npos) << header;
}

}  // namespace
}  // namespace kiln
