// The denoiser's half-buffers in the film: even samples in half A, odd in half B by sample index,
// adding up to the film's own sums exactly, and the same bits through checkpoint, resume,
// refinement and sample-range/crop merges; a film without them renders as before.
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

struct HalfRenders : test::LoadedSpheres {
    fs::path dir = test::scratchDir();
    RenderJobOptions options(int spp, const AovRequest& aovs = withHalves()) const {
        return test::jobOptions(24, 18, spp, {}, aovs);
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
    Film whole(int spp, const AovRequest& aovs = withHalves()) const {
        return test::renderJob(scene, *accel, options(spp, aovs));
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

TEST(HalfBuffers, ExactThroughCheckpointResumeAndRefinement) {
    HalfRenders r;
    LongRenderResult done = r.run("a", 0, 16);
    CheckpointInfo info;
    Film back = readCheckpoint((r.dir / "a.ckpt").string(), info);
    EXPECT_TRUE(back.hasHalves());
    EXPECT_EQ(test::filmState(back), test::filmState(done.film));
    r.run("b", 0, 5);
    LongRenderResult refined = r.run("b", 0, 16, true);
    EXPECT_TRUE(refined.resumed);
    EXPECT_EQ(test::filmState(refined.film), test::filmState(r.whole(16)));
}

// Shards starting at odd samples put their first sample in half B: the split follows the index.
TEST(HalfBuffers, ExactThroughSampleRangeAndCropMerges) {
    HalfRenders r;
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

// Keeping the halves adds buffers and nothing else: every other buffer holds the same bits.
TEST(HalfBuffers, AFilmWithoutThemHoldsTheSameBitsAsBefore) {
    HalfRenders r;
    Film plain = r.whole(6, AovRequest::defaults()), kept = r.whole(6);
    EXPECT_FALSE(plain.hasHalves());
    std::vector<FilmBuffer> a = plain.buffers(), b = kept.buffers();
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
        if (a[k].name.rfind("denoise_", 0) == 0) {
            EXPECT_EQ(a[k].perPixel, 0u) << a[k].name;
            continue;
        }
        ASSERT_EQ(a[k].bytes(plain.pixelCount()), b[k].bytes(kept.pixelCount())) << a[k].name;
        EXPECT_EQ(std::memcmp(a[k].data, b[k].data, a[k].bytes(plain.pixelCount())), 0)
            << a[k].name;
    }
}

}  // namespace
}  // namespace kiln
