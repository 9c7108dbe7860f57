// The NFOR denoiser (renderer/denoise): deterministic for any thread count, a constant and a
// noise-free image unchanged, NaN/Inf kept local, a rendered frame's error reduced; kiln render
// --denoise and kiln denoise write the denoised beauty beside the noisy one and refuse bad EXRs.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "color/exr_image.h"
#include "denoise_support.h"
#include "kiln_run.h"
#include "long_render_support.h"
#include "renderer/denoise/denoiser.h"
#include "renderer/denoise_film.h"
#include "renderer/validation/accuracy.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using denoise::Halves;
using denoise::Image;

constexpr int kChannels = 13;  // colour, its variance, albedo, normal, depth (half_buffers.h)

// Smooth colour and features with independent Gaussian noise per half (seeded), each colour's
// variance stated.
Halves syntheticHalves(int w, int h, float colourNoise, float featureNoise, uint32_t seed = 7) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    Halves halves;
    for (Image& half : halves.half) {
        half = Image(w, h, kChannels);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float* p = half.at(x, y);
                float albedo = x < w / 2 ? 0.8f : 0.2f;  // a texture edge
                for (int c = 0; c < 3; ++c) {
                    float shade = 0.3f + 0.5f * std::sin(0.1f * x + 0.07f * y + c);
                    float sd = colourNoise * albedo * shade;
                    p[c] = albedo * shade + sd * gauss(rng);
                    p[3 + c] = sd * sd;
                    p[6 + c] = albedo + featureNoise * gauss(rng);
                }
                p[9] = 0.0f, p[10] = 0.6f, p[11] = 0.8f;
                p[12] = 2.0f + 0.01f * float(y) + featureNoise * gauss(rng);
            }
    }
    return halves;
}

std::vector<Color> meanOf(const Halves& halves) {
    std::vector<Color> m(halves.half[0].pixels());
    for (size_t p = 0; p < m.size(); ++p)
        for (int c = 0; c < 3; ++c)
            m[p][c] = 0.5f * (halves.half[0].values[p * kChannels + size_t(c)] +
                              halves.half[1].values[p * kChannels + size_t(c)]);
    return m;
}

// CBspheres at 96x72, 16 spp, with the denoiser's half-buffers.
constexpr int kSpheresW = 96, kSpheresH = 72;
Film sixteenSampleSpheres(const test::LoadedSpheres& s) {
    AovRequest aovs;
    aovs.add(AovKind::DenoiseHalves);
    return test::renderJob(s.scene, *s.accel, test::jobOptions(kSpheresW, kSpheresH, 16, {}, aovs));
}

bool sameBits(const std::vector<Color>& a, const std::vector<Color>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Color)) == 0;
}

TEST(Denoiser, BitIdenticalForAnyThreadCount) {
    Halves halves = syntheticHalves(75, 41, 0.5f, 0.05f);  // not a multiple of the tiles
    std::vector<Color> one = denoise::denoise(halves, {.threads = 1});
    for (int threads : {2, 3, 8}) {
        denoise::Options o;
        o.threads = threads;
        EXPECT_TRUE(sameBits(denoise::denoise(halves, o), one)) << threads << " threads";
    }
}

// A beauty and a light-path layer share the features: denoised together (the features
// prefiltered once) each comes back with the bits it has denoised alone.
TEST(Denoiser, ImagesSharingTheFeaturesGiveWhatEachGivesAlone) {
    Halves beauty = syntheticHalves(70, 40, 0.5f, 0.05f, 7);
    Halves layer = syntheticHalves(70, 40, 0.8f, 0.05f, 9);
    for (int h = 0; h < 2; ++h)  // the layer's colour and variance, the beauty's features
        for (size_t p = 0; p < layer.half[h].pixels(); ++p)
            for (int c = 6; c < kChannels; ++c)
                layer.half[h].values[p * kChannels + size_t(c)] =
                    beauty.half[h].values[p * kChannels + size_t(c)];
    const Halves* frames[2] = {&beauty, &layer};
    std::vector<std::vector<Color>> both =
        denoise::denoiseAll(2, [&frames](size_t i) { return *frames[i]; });
    EXPECT_TRUE(sameBits(both[0], denoise::denoise(beauty)));
    EXPECT_TRUE(sameBits(both[1], denoise::denoise(layer)));
    EXPECT_FALSE(sameBits(both[0], both[1]));
}

TEST(Denoiser, AConstantImageComesBackUnchanged) {
    Halves halves = syntheticHalves(40, 36, 0.0f, 0.1f);  // noisy features
    for (Image& half : halves.half)
        for (size_t p = 0; p < half.pixels(); ++p)
            for (int c = 0; c < 3; ++c) {
                half.values[p * kChannels + size_t(c)] = 0.25f * float(c + 1);
                half.values[p * kChannels + size_t(3 + c)] = 0.0f;
            }
    std::vector<Color> out = denoise::denoise(halves);
    for (const Color& c : out)
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(c[k], 0.25f * float(k + 1), 1e-6f);
}

TEST(Denoiser, ANoiseFreeImageComesBackUnchanged) {
    Halves halves = syntheticHalves(40, 36, 0.0f, 0.0f);
    halves.half[1] = halves.half[0];  // both halves agree: no noise anywhere
    std::vector<Color> in = meanOf(halves), out = denoise::denoise(halves);
    for (size_t p = 0; p < in.size(); ++p)
        for (int k = 0; k < 3; ++k)
            ASSERT_NEAR(out[p][k], in[p][k], 2e-7f * std::max(1.0f, std::fabs(in[p][k]))) << p;
}

// A NaN and an Inf sample in one pixel change nothing beyond the reach of the filters there
// (the passes' windows and patches summed: under 80 pixels).
TEST(Denoiser, NonFiniteValuesNeverSpread) {
    const int w = 128, h = 24, reach = 80;
    Halves clean = syntheticHalves(w, h, 0.3f, 0.02f), bad = clean;
    bad.half[0].at(10, 10)[1] = std::numeric_limits<float>::quiet_NaN();
    bad.half[1].at(10, 10)[2] = std::numeric_limits<float>::infinity();
    bad.half[1].at(10, 10)[8] = -std::numeric_limits<float>::infinity();
    bad.half[0].at(10, 10)[4] = std::numeric_limits<float>::quiet_NaN();
    std::vector<Color> a = denoise::denoise(clean), b = denoise::denoise(bad);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Color& c = b[size_t(y) * w + size_t(x)];
            ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
            if (x > 10 + reach) {
                ASSERT_EQ(c.x, a[size_t(y) * w + size_t(x)].x) << x << " " << y;
            }
        }
}

TEST(Denoiser, UnusableHalvesAreNamed) {
    Halves halves = syntheticHalves(8, 8, 0.1f, 0.1f);
    EXPECT_EQ(denoise::problemWith(halves), "");
    halves.half[1] = Image(8, 9, kChannels);
    EXPECT_NE(denoise::problemWith(halves).find("differ in size"), std::string::npos);
}

// CBspheres at 16 spp against 1024 spp. The reference's own noise adds 16/1024 of the raw error
// to both measured errors (no more than the margin); the denoised error must lie below the raw
// one by more than three standard errors of the per-pixel drop. Paired over pixels, as the
// layers' test: the raw error's spread is a few fireflies, which two independent standard errors
// counted against the drop they make (on one machine the same code rendered 0.0093 +- 0.0018 raw
// against 0.0036 +- 0.0008 denoised, which the unpaired test failed).
TEST(Denoiser, LowersTheErrorOfASixteenSampleRender) {
    test::LoadedSpheres s;
    Film noisy = sixteenSampleSpheres(s);
    std::vector<Color> reference = test::beautyOf(
        test::renderJob(s.scene, *s.accel, test::jobOptions(kSpheresW, kSpheresH, 1024)));
    const std::vector<Color> raw = test::beautyOf(noisy), denoised = *denoiseFilm(noisy, {});
    test::RelMse drop = test::relMseDrop(denoised, raw, reference);
    EXPECT_GT(drop.mean, 3 * drop.standardError)
        << "raw " << test::relMseOf(raw, reference).mean << ", denoised "
        << test::relMseOf(denoised, reference).mean << ": the relMSE drops by " << drop.mean
        << " +- " << drop.standardError;
}

// Planes fitted across an edge (the light's rim, the box's outline against black) overshoot
// below zero beside it: session 13's denoiser gave thousands of negative pixels on this frame.
// Light is never negative, so neither is a denoised frame whose samples are not.
TEST(Denoiser, NeverNegativeWhereNoSampleIs) {
    test::LoadedSpheres s;
    Film film = sixteenSampleSpheres(s);
    for (const Color& c : test::beautyOf(film)) ASSERT_GE(std::min({c.x, c.y, c.z}), 0.0f);
    const std::vector<Color> denoised = *denoiseFilm(film, {});
    int negative = 0;
    for (const Color& c : denoised) negative += std::min({c.x, c.y, c.z}) < 0;
    EXPECT_EQ(negative, 0);
}

// A fine texture (slanted stripes 1.8 pixels wide, two colours) under smooth shading, that each
// half samples at its own 8 points per pixel (a 16-spp render) with 30 % colour noise: a half's
// albedo and colour follow where its own samples fell, as in a render. The truth and its
// albedo come from a 16x16 grid per pixel.
struct StripedFrame {
    int w = 96, h = 96;
    Halves halves;
    std::vector<Color> truth;
    std::vector<Color> trueAlbedo;
};

StripedFrame stripedFrame(uint32_t seed) {
    StripedFrame f;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    auto texture = [](float x, float y) {
        return std::fmod(x + 0.37f * y, 3.6f) < 1.8f ? Color(0.8f, 0.6f, 0.3f)
                                                     : Color(0.1f, 0.25f, 0.5f);
    };
    auto shade = [](int x, int y, int c) {
        return 0.6f + 0.2f * std::sin(0.05f * float(x + y) + float(c));
    };
    for (Image& half : f.halves.half) half = Image(f.w, f.h, kChannels);
    for (int y = 0; y < f.h; ++y)
        for (int x = 0; x < f.w; ++x) {
            Color fine(0.0f);
            for (int i = 0; i < 256; ++i)
                fine += texture(float(x) + (float(i % 16) + 0.5f) / 16,
                                float(y) + (float(i / 16) + 0.5f) / 16) /
                        256.0f;
            f.trueAlbedo.push_back(fine);
            f.truth.push_back(fine * Color(shade(x, y, 0), shade(x, y, 1), shade(x, y, 2)));
            for (Image& half : f.halves.half) {
                Color albedo(0.0f);
                for (int s = 0; s < 8; ++s) {
                    const float sx = jitter(rng), sy = jitter(rng);  // in this order
                    albedo += texture(float(x) + sx, float(y) + sy) / 8.0f;
                }
                float* p = half.at(x, y);
                for (int c = 0; c < 3; ++c) {
                    const float sd = 0.3f * albedo[c] * shade(x, y, c);
                    p[c] = albedo[c] * shade(x, y, c) + sd * gauss(rng);
                    p[3 + c] = sd * sd;
                    p[6 + c] = albedo[c];
                }
                p[9] = 0.0f, p[10] = 0.0f, p[11] = 1.0f, p[12] = 3.0f;
            }
        }
    return f;
}

// The image's albedo-edge contrast against the truth (the accuracy report's measure).
double edgeContrast(const StripedFrame& f, const std::vector<Color>& image) {
    return albedoEdgeContrast(::kiln::Image{f.w, f.h, image, {}, {}, {}},
                              ::kiln::Image{f.w, f.h, f.truth, {}, {}, {}}, f.trueAlbedo);
}

// Issue 29's goal on texture edges, the denoised albedo-edge contrast within 2 % of the
// reference's (here the truth's), over 8 frames; and no softer than the raw input's, on average
// beyond three standard errors of the frames' differences. Measured: 0.993-1.011, -0.4 to +0.2 %
// beside the raw input. Regressed on the other half's features, whose samples fell elsewhere in
// the pixel, the fit flattens its slope on albedo: 0.982-0.999, so the goal alone would not tell,
// but 1.0-1.6 % below the raw input on every frame (mean 1.19 %, its standard error 0.07 %).
TEST(Denoiser, KeepsATextureEdgeThatEachHalfCoversWithItsOwnSamples) {
    std::vector<double> softening;
    for (uint32_t seed = 1; seed <= 8; ++seed) {
        const StripedFrame f = stripedFrame(seed);
        const double raw = edgeContrast(f, meanOf(f.halves));
        const double denoised = edgeContrast(f, denoise::denoise(f.halves));
        EXPECT_GT(denoised, 0.98) << "seed " << seed;
        softening.push_back(raw - denoised);
    }
    const test::RelMse mean = test::meanOf(softening);
    EXPECT_LT(mean.mean, 3 * mean.standardError) << mean.mean << " +- " << mean.standardError;
}

// One sample per pixel leaves half B empty: it takes half A's values and the pixel stays as it is.
TEST(Denoiser, ASingleSampleRenderComesBackUnchanged) {
    test::LoadedSpheres s;
    AovRequest aovs;
    aovs.add(AovKind::DenoiseHalves);
    Film film = test::renderJob(s.scene, *s.accel, test::jobOptions(40, 30, 1, {}, aovs));
    std::vector<Color> out = *denoiseFilm(film, {});
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c) {
                float raw = film.pixel(x, y)[c];
                ASSERT_NEAR(out[size_t(y) * 40 + size_t(x)][c], raw,
                            1e-6f * std::max(1.0f, std::fabs(raw)))
                    << x << " " << y;
            }
}

// kiln render --denoise: R,G,B denoised, the raw beauty as noisy.*, the halves and the header;
// kiln denoise of that EXR gives the same R,G,B.
TEST(DenoiseCommand, RenderAndDenoiseWriteTheDenoisedBeautyBesideTheNoisyOne) {
    fs::path dir = test::scratchDir();
    std::string out = (dir / "a").string();
    test::CliRun r = test::runKiln("render " + test::shellQuoted(test::spheres()) +
                                   " -r 40 30 -s 8 -q --denoise -t 2 -o " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    ExrImage exr = ExrImage::read(out + ".exr");
    EXPECT_NE(exr.attribute("kiln:denoised").find("NFOR"), std::string::npos);
    ASSERT_GE(exr.channel("noisy.R"), 0);
    ASSERT_GE(exr.channel("halfB.n"), 0);
    bool differs = false;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            differs |= exr.value(x, y, exr.channel("R")) != exr.value(x, y, exr.channel("noisy.R"));
    EXPECT_TRUE(differs);
    test::CliRun d = test::runKiln("denoise " + out + ".exr -t 1 -o " + out + "-again.exr");
    ASSERT_EQ(d.code, 0) << d.err;
    ExrImage again = ExrImage::read(out + "-again.exr");
    for (const char* c : {"R", "G", "B", "noisy.R"})
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x)
                ASSERT_EQ(again.value(x, y, again.channel(c)), exr.value(x, y, exr.channel(c)))
                    << c << " " << x << " " << y;
}

// Bad input: one line naming the file and the problem, exit 2.
TEST(DenoiseCommand, ExrsWithoutUsableHalfBuffersAreRefused) {
    fs::path dir = test::scratchDir();
    std::string out = (dir / "plain").string();
    ASSERT_EQ(test::runKiln("render " + test::shellQuoted(test::spheres()) +
                            " -r 16 12 -s 2 -q -o " + out)
                  .code,
              0);
    ASSERT_EQ(test::runKiln("render " + test::shellQuoted(test::spheres()) +
                            " -r 16 12 -s 2 -q --denoise -o " + out + "-halves")
                  .code,
              0);
    auto refused = [&](const std::string& file, const std::string& why) {
        test::CliRun r = test::runKiln("denoise " + file + " -o " + (dir / "x.exr").string());
        EXPECT_EQ(r.code, 2) << r.err;
        EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "x.exr"));
    };
    refused(out + ".exr", "carries no half-buffers");
    refused((dir / "missing.exr").string(), "cannot read");
    auto edited = [&](const std::string& name, const std::string& channel, float value) {
        ExrImage exr = ExrImage::read(out + "-halves.exr");
        std::vector<float> plane(size_t(exr.width()) * exr.height());
        for (size_t p = 0; p < plane.size(); ++p)
            plane[p] = exr.value(int(p % 16), int(p / 16), exr.channel(channel));
        plane[5] = value;
        exr.setChannel(channel, plane, false);
        std::string path = (dir / name).string();
        exr.write(path);
        return path;
    };
    refused(edited("nan.exr", "halfA.G", std::nanf("")), "non-finite value in halfA.G");
    refused(edited("count.exr", "halfB.n", 99.0f), "do not add up to samples.X");
    // A file with half A only.
    OIIO::ImageSpec spec(4, 4, 0, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B"};
    for (const std::string& c : halfBufferChannels(0)) spec.channelnames.push_back(c);
    spec.nchannels = int(spec.channelnames.size());
    std::vector<float> zeros(size_t(16) * size_t(spec.nchannels), 0.0f);
    std::string halfA = (dir / "half-a.exr").string();
    auto o = OIIO::ImageOutput::create(halfA);
    ASSERT_TRUE(o->open(halfA, spec) && o->write_image(OIIO::TypeDesc::FLOAT, zeros.data()));
    o->close();
    refused(halfA, "incomplete half-buffers: no channel halfB.R");
}

}  // namespace
}  // namespace kiln
