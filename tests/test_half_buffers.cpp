// The denoiser's half-buffers in the film: even samples in half A, odd in half B by sample index,
// adding up to the film's own sums exactly, and the same bits through checkpoint, resume,
// refinement and sample-range/crop merges; a film without them renders as before. The same for
// the half-buffers of denoised light-path layers (--denoise-aovs), kept only when asked for.
#include <cstring>

#include "long_render_support.h"
#include "renderer/long_render.h"
#include "renderer/shard_merge.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

AovRequest withHalves() {
    AovRequest aovs = AovRequest::defaults();
    aovs.add(AovKind::DenoiseHalves);
    return aovs;
}

// --denoise --denoise-aovs direct,indirect_diffuse: halves of a layer of the defaults and of a
// per-lobe one.
AovRequest withLayerHalves() {
    AovRequest aovs = withHalves();
    aovs.add(AovKind::IndirectDiffuse);
    aovs.denoisedLight = AovRequest::parseDenoised("direct,indirect_diffuse");
    return aovs;
}

struct HalfRenders : test::LoadedSpheres {
    AovRequest aovs = withHalves();
    fs::path dir = test::scratchDir();
    RenderJobOptions options(int spp) const { return options(spp, aovs); }
    RenderJobOptions options(int spp, const AovRequest& request) const {
        return test::jobOptions(24, 18, spp, {}, request);
    }
    // Samples [a, b) of region x [x0, x1) (x1 = 0: whole) into a checkpoint; resume: refine it.
    LongRenderResult run(const std::string& name, int a, int b, bool resume = false, int x0 = 0,
                         int x1 = 0) const {
        RenderJobOptions o = options(b);
        o.settings.sampleStart = a;
        o.settings.regionX0 = x0, o.settings.regionX1 = x1;
        if (x1 > 0) o.settings.regionY0 = 0, o.settings.regionY1 = 18;
        RenderJob job(scene, *accel, o);
        LongRenderOptions lo;
        lo.checkpointPath = (dir / (name + ".ckpt")).string();
        lo.resume = resume;
        lo.fingerprint = checkpointFingerprint(job, test::spheres(), {});
        return runLongRender(job, lo);
    }
    Film whole(int spp) const { return whole(spp, aovs); }
    Film whole(int spp, const AovRequest& request) const {
        return test::renderJob(scene, *accel, options(spp, request));
    }
};

const FilmBuffer& bufferNamed(const std::vector<FilmBuffer>& buffers, const std::string& name) {
    for (const FilmBuffer& b : buffers)
        if (b.name == name) return b;
    throw std::logic_error("no film buffer " + name);
}

TEST(HalfBuffers, EvenAndOddSamplesAddUpToTheFilmsSumsExactly) {
    HalfRenders r;
    Film film = r.whole(7);
    ASSERT_TRUE(film.hasHalves());
    std::vector<FilmBuffer> buffers = film.buffers();
    const auto* beauty = static_cast<const FixedSum*>(bufferNamed(buffers, "beauty").data);
    const auto* halves = static_cast<const FixedSum*>(bufferNamed(buffers, "denoise_halves").data);
    for (size_t i = 0; i < film.pixelCount(); ++i) {
        int x = int(i % 24), y = int(i / 24);
        EXPECT_EQ(film.halfSamples(x, y, 0), 4u);  // samples 0, 2, 4, 6
        EXPECT_EQ(film.halfSamples(x, y, 1), 3u);
        for (int c = 0; c < 3; ++c)
            ASSERT_TRUE(halves[i * 2 * kHalfSums + size_t(c)] +
                            halves[(i * 2 + 1) * kHalfSums + size_t(c)] ==
                        beauty[3 * i + size_t(c)])
                << x << " " << y;
    }
}

// Each denoised layer's halves add up to its AOV sums (a layer of the defaults and a per-lobe
// one), after the beauty's kHalfSums.
TEST(HalfBuffers, LayerHalvesAddUpToTheLayersSumsExactly) {
    HalfRenders r;
    Film film = r.whole(7, withLayerHalves());
    const std::vector<DenoisedLayer>& layers = film.layout().denoisedLayers();
    ASSERT_EQ(layers.size(), 2u);
    EXPECT_EQ(layers[0].name, "direct");
    EXPECT_EQ(layers[1].name, "indirect_diffuse");
    std::vector<FilmBuffer> buffers = film.buffers();
    const FilmBuffer& halfBuffer = bufferNamed(buffers, "denoise_halves");
    const size_t stride = kHalfSums + 2 * kLayerHalfSums;
    ASSERT_EQ(halfBuffer.perPixel, 2 * stride);
    const auto* halves = static_cast<const FixedSum*>(halfBuffer.data);
    const auto* aov = static_cast<const FixedSum*>(bufferNamed(buffers, "aov").data);
    const size_t aovChannels = bufferNamed(buffers, "aov").perPixel;
    bool lit = false;
    for (size_t i = 0; i < film.pixelCount(); ++i)
        for (size_t l = 0; l < layers.size(); ++l)
            for (size_t c = 0; c < 3; ++c) {
                const size_t at = kHalfSums + l * kLayerHalfSums + c;
                // The layout's channels are all summed ones here, so aov's slot is the channel.
                const FixedSum sum = aov[i * aovChannels + layers[l].channel + c];
                ASSERT_TRUE(halves[i * 2 * stride + at] + halves[i * 2 * stride + stride + at] ==
                            sum)
                    << i << " " << layers[l].name;
                lit |= sum != 0;
            }
    EXPECT_TRUE(lit);
}

void checkpointResumeAndRefine(const HalfRenders& r) {
    LongRenderResult done = r.run("a", 0, 16);
    CheckpointInfo info;
    Film back = readCheckpoint((r.dir / "a.ckpt").string(), info);
    EXPECT_TRUE(back.hasHalves());
    EXPECT_EQ(info.aovs.denoisedLight, r.aovs.denoisedLight);
    EXPECT_EQ(test::filmState(back), test::filmState(done.film));
    r.run("b", 0, 5);
    LongRenderResult refined = r.run("b", 0, 16, true);
    EXPECT_TRUE(refined.resumed);
    EXPECT_EQ(test::filmState(refined.film), test::filmState(r.whole(16)));
}

// A check run on the beauty's halves alone, then with layer halves too.
void withEachKindOfHalves(void (*check)(const HalfRenders&)) {
    HalfRenders r;
    for (const AovRequest& aovs : {withHalves(), withLayerHalves()}) {
        r.aovs = aovs;
        SCOPED_TRACE(aovs.denoisedLight ? "with layer halves" : "beauty halves");
        check(r);
    }
}

TEST(HalfBuffers, ExactThroughCheckpointResumeAndRefinement) {
    withEachKindOfHalves(checkpointResumeAndRefine);
}

// A checkpoint made without --denoise-aovs is another render's: resuming it with them is refused.
TEST(HalfBuffers, LayerHalvesAreInTheCheckpointFingerprint) {
    HalfRenders r;
    RenderJob beauty(r.scene, *r.accel, r.options(4, withHalves()));
    RenderJob layers(r.scene, *r.accel, r.options(4, withLayerHalves()));
    std::string why =
        fingerprintDifference(checkpointFingerprint(beauty, test::spheres(), {}),
                              checkpointFingerprint(layers, test::spheres(), {}), "a.ckpt");
    EXPECT_NE(why.find("denoised direct,indirect_diffuse"), std::string::npos) << why;
}

// Shards starting at odd samples put their first sample in half B: the split follows the index.
void mergeShardsExactly(const HalfRenders& r) {
    std::vector<std::string> ranges;
    for (auto [name, a, b] : {std::tuple{"s1", 3, 10}, {"s0", 0, 3}, {"s2", 10, 16}}) {
        r.run(name, a, b);
        ranges.push_back((r.dir / (std::string(name) + ".ckpt")).string());
    }
    Film one = r.whole(16);
    EXPECT_EQ(test::filmState(mergeShards(ranges).film), test::filmState(one));
    r.run("left", 0, 16, false, 0, 11);
    r.run("right", 0, 16, false, 11, 24);
    MergedRender crops =
        mergeShards({(r.dir / "left.ckpt").string(), (r.dir / "right.ckpt").string()});
    EXPECT_EQ(test::filmState(crops.film), test::filmState(one));
}

TEST(HalfBuffers, ExactThroughSampleRangeAndCropMerges) {
    withEachKindOfHalves(mergeShardsExactly);
}

// Keeping the halves adds buffers and nothing else: every other buffer holds the same bits. Layer
// halves only lengthen each half: the beauty's sums in it are those of a film without them.
TEST(HalfBuffers, AFilmWithoutThemHoldsTheSameBitsAsBefore) {
    HalfRenders r;
    Film plain = r.whole(6, AovRequest::defaults()), kept = r.whole(6),
         layered = r.whole(6, withLayerHalves());
    EXPECT_FALSE(plain.hasHalves());
    std::vector<FilmBuffer> a = plain.buffers(), b = kept.buffers(), c = layered.buffers();
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), c.size());
    for (size_t k = 0; k < a.size(); ++k) {
        if (a[k].name.rfind("denoise_", 0) == 0) {
            EXPECT_EQ(a[k].perPixel, 0u) << a[k].name;
            continue;
        }
        ASSERT_EQ(a[k].bytes(plain.pixelCount()), b[k].bytes(kept.pixelCount())) << a[k].name;
        EXPECT_EQ(std::memcmp(a[k].data, b[k].data, a[k].bytes(plain.pixelCount())), 0)
            << a[k].name;
    }
    const FilmBuffer& beautyOnly = bufferNamed(b, "denoise_halves");
    EXPECT_EQ(beautyOnly.perPixel, 2u * kHalfSums);
    const FilmBuffer& withLayers = bufferNamed(c, "denoise_halves");
    ASSERT_EQ(withLayers.perPixel, beautyOnly.perPixel + 2 * 2 * kLayerHalfSums);
    EXPECT_EQ(std::memcmp(bufferNamed(b, "denoise_half_samples").data,
                          bufferNamed(c, "denoise_half_samples").data,
                          bufferNamed(b, "denoise_half_samples").bytes(kept.pixelCount())),
              0);
    const auto* halves = static_cast<const FixedSum*>(beautyOnly.data);
    const auto* longer = static_cast<const FixedSum*>(withLayers.data);
    const size_t stride = withLayers.perPixel / 2;
    for (size_t half = 0; half < 2 * kept.pixelCount(); ++half)
        ASSERT_EQ(std::memcmp(halves + half * kHalfSums, longer + half * stride,
                              kHalfSums * sizeof(FixedSum)),
                  0)
            << half;
}

}  // namespace
}  // namespace kiln
