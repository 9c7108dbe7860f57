// The render loop, normal shading with both accelerators, and the EXR/PNG output.
#include <OpenImageIO/imageio.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>

#include "color/image_output.h"
#include "integrators/normals.h"
#include "integrators/path.h"
#include "renderer/accel/recording_accelerator.h"
#include "renderer/render_loop.h"
#include "renderer/tile_schedule.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

Film renderNormals(const Scene& s, const Accelerator& accel, RenderSettings settings) {
    NormalsIntegrator integrator(s, accel);
    Film film(settings.width, settings.height);
    settings.progress = false;
    renderImage(s, integrator, settings, film);
    return film;
}

TEST(NormalsRender, EmbreeAndReferenceImagesMatch) {
    for (const char* scene : {"sky/CBspheres.dae", "sky/CBbunny.dae", "meshedit/cow.dae"}) {
        Scene s = loadScene(test::cs184(scene));
        RenderSettings settings;
        settings.width = 160, settings.height = 120, settings.spp = 4;
        auto embree = makeEmbreeAccelerator(s);
        auto reference = makeReferenceAccelerator(s);
        Film a = renderNormals(s, *embree, settings), b = renderNormals(s, *reference, settings);
        int differing = 0;
        double sumDiff = 0;
        for (int y = 0; y < a.height(); ++y)
            for (int x = 0; x < a.width(); ++x) {
                float d = maxComponent(abs(a.pixel(x, y) - b.pixel(x, y)));
                sumDiff += d;
                differing += d > 1e-3f;
            }
        // Identical except where a sample lands within float rounding of an edge between two faces.
        EXPECT_LE(differing, a.width() * a.height() / 200) << scene;
        EXPECT_LT(sumDiff / (a.width() * a.height()), 1e-3) << scene;
    }
}

TEST(RenderLoop, BitIdenticalWhateverTheThreadsAndTiles) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RenderSettings one;
    one.width = 97, one.height = 61, one.spp = 5, one.threads = 1, one.tileSize = 7;
    RenderSettings many = one;
    many.threads = 4, many.tileSize = 32;
    Film a = renderNormals(s, *accel, one), b = renderNormals(s, *accel, many);
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            ASSERT_EQ(a.pixel(x, y), b.pixel(x, y)) << x << "," << y;
            ASSERT_EQ(a.samples(x, y), 5u);
        }
    // A different seed moves the jitter, so some pixel changes.
    RenderSettings other = one;
    other.seed = 99;
    Film c = renderNormals(s, *accel, other);
    bool changed = false;
    for (int y = 0; y < a.height() && !changed; ++y)
        for (int x = 0; x < a.width() && !changed; ++x) changed = !(a.pixel(x, y) == c.pixel(x, y));
    EXPECT_TRUE(changed);
}

TEST(TileSchedule, CostliestFirstKeepsTheImageOrderAmongEquals) {
    EXPECT_EQ(costliestFirst({1.0, 3.0, 0.0, 3.0, 2.0}), (std::vector<int>{1, 3, 4, 0, 2}));
    EXPECT_EQ(costliestFirst({0.0, 0.0, 0.0}), (std::vector<int>{0, 1, 2}));  // a first wave
    EXPECT_TRUE(costliestFirst({}).empty());
}

TEST(TileSchedule, EveryTileOnceAndOneWorkerInOrder) {
    std::vector<double> seconds(101);
    for (size_t i = 0; i < seconds.size(); ++i) seconds[i] = double((i * 37) % 11);
    const std::vector<int> order = costliestFirst(seconds);
    for (int workers : {1, 2, 4, 7, 300}) {
        std::vector<std::atomic<int>> visits(order.size());
        std::vector<int> sequence;
        std::mutex m;
        tbb::task_arena arena(4);
        arena.execute([&] {
            forEachTileInOrder(order, workers, [&](int t) {
                ++visits[size_t(t)];
                std::lock_guard lock(m);
                sequence.push_back(t);
            });
        });
        for (size_t t = 0; t < visits.size(); ++t) ASSERT_EQ(visits[t].load(), 1) << workers;
        if (workers == 1) {
            EXPECT_EQ(sequence, order);
        }
    }
}

TEST(TileSchedule, AThrowingTileReachesTheCallerAndStopsTheRest) {
    std::vector<int> order(50);
    std::iota(order.begin(), order.end(), 0);
    for (int workers : {1, 4}) {
        std::atomic<int> started{0};
        tbb::task_arena arena(4);
        auto run = [&] {
            arena.execute([&] {
                forEachTileInOrder(order, workers, [&](int t) {
                    ++started;
                    if (t == 10) throw std::runtime_error("tile 10");
                    // A tile takes far longer than the throw: the others stop within a tile.
                    std::this_thread::sleep_for(std::chrono::milliseconds(2));
                });
            });
        };
        EXPECT_THROW(run(), std::runtime_error) << workers;
        // Tiles 0-10, and a tile or two more for each other worker (without the stop, all 50).
        EXPECT_LE(started.load(), 11 + 2 * (workers - 1)) << workers;
    }
}

// Interrupts the render after a fixed number of camera samples, as SIGINT would.
class InterruptingIntegrator final : public Integrator {
  public:
    InterruptingIntegrator(const Scene& s, const Accelerator& a, int after)
        : Integrator(s, a), inner_(s, a), after_(after) {}
    using Integrator::Li;
    void Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
            SampleRecord& record) const override {
        if (++calls_ == after_) renderCancelFlag().store(true);
        inner_.Li(ray, sampler, counter, record);
    }
    const char* name() const override { return "interrupting"; }

  private:
    NormalsIntegrator inner_;
    int after_;
    mutable std::atomic<int> calls_{0};
};

TEST(RenderLoop, InterruptKeepsTrueSampleCountsAndWritesThem) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    InterruptingIntegrator integrator(s, *accel, 20000);
    RenderSettings settings;
    settings.width = 64, settings.height = 48, settings.spp = 64, settings.progress = false;
    Film film(settings.width, settings.height, AovRequest::defaults());
    renderCancelFlag().store(false);
    RenderStats stats = renderImage(s, integrator, settings, film);
    renderCancelFlag().store(false);
    EXPECT_TRUE(stats.interrupted);
    EXPECT_LT(stats.samples, uint64_t(64) * 64 * 48);
    EXPECT_GE(stats.samples, 20000u);
    uint32_t maxCount = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) maxCount = std::max(maxCount, film.samples(x, y));
    EXPECT_LT(maxCount, 64u);

    auto path = (test::scratchDir() / "partial.exr").string();
    writeExr(path, film, {{"interrupted", "yes"}});
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    int samplesChannel = spec.channelindex("samples.X");
    ASSERT_GE(samplesChannel, 0);
    std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            ASSERT_EQ(pixels[(size_t(y) * 64 + x) * spec.nchannels + samplesChannel],
                      float(film.samples(x, y)));
}

TEST(ImageOutput, ExrRoundTripKeepsChannelsValuesAndMetadata) {
    Film film(8, 4, AovRequest::defaults());
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            for (int k = 0; k <= x; ++k) film.add(x, y, Color(0.1f * x, 0.5f * y, 100.0f));
    auto path = (test::scratchDir() / "round.exr").string();
    writeExr(path, film, {{"spp", "8"}, {"integrator", "normals"}});
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    for (const char* ch : {"R", "G", "B", "A", "samples.X"})
        EXPECT_GE(spec.channelindex(ch), 0) << ch;
    EXPECT_EQ(spec.get_int_attribute("kiln:spp"), 8);
    EXPECT_EQ(spec.get_string_attribute("kiln:integrator"), "normals");
    EXPECT_EQ(spec.get_string_attribute("kiln:colorspace"), "lin_rec709");
    EXPECT_NE(spec.find_attribute("chromaticities"), nullptr);
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    int r = spec.channelindex("R"), b = spec.channelindex("B"), n = spec.channelindex("samples.X");
    EXPECT_FLOAT_EQ(px[(3 * 8 + 5) * spec.nchannels + r], 0.5f);
    EXPECT_FLOAT_EQ(px[(3 * 8 + 5) * spec.nchannels + b], 100.0f);
    EXPECT_FLOAT_EQ(px[(3 * 8 + 5) * spec.nchannels + n], 6.0f);
}

TEST(ImageOutput, StandardViewIsTheSrgbCurve) {
    EXPECT_NEAR(displayTransform(0.18f), 0.4614f, 1e-4f);
    EXPECT_NEAR(displayTransform(0.0f), 0.0f, 1e-6f);
    EXPECT_NEAR(displayTransform(1.0f), 1.0f, 1e-5f);
    EXPECT_NEAR(displayTransform(0.002f), 0.002f * 12.92f, 1e-5f);  // the linear toe
    EXPECT_NEAR(displayTransform(0.18f, "sRGB", "Raw"), 0.18f, 1e-6f);
}

TEST(TraversalFloor, ReplaysExactlyTheCallsOfTheRender) {
    // The recorder must not change the render, must hold every ray the render counted, and its
    // replay must make the same calls with the same answers: otherwise the floor it times is
    // some other workload.
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RecordingAccelerator recorder(*accel);
    RenderSettings settings;
    settings.width = 40, settings.height = 30, settings.spp = 4, settings.threads = 2;
    settings.progress = false;
    PathOptions opt;
    opt.lightSamples = 2;
    RenderJobOptions o = test::jobOptions(settings.width, settings.height, settings.spp, opt);
    o.settings = settings;
    // As --traversal-floor does: the same job (its plan analysed once) traced through the recorder.
    RenderJob job(s, *accel, o), again(job, recorder);
    RenderStats plain, recorded;
    Film a = job.makeFilm(), b = again.makeFilm();
    plain = job.render(a);
    recorded = again.render(b);
    for (int y = 0; y < settings.height; ++y)
        for (int x = 0; x < settings.width; ++x) ASSERT_EQ(a.pixel(x, y), b.pixel(x, y));
    EXPECT_EQ(recorded.rays, plain.rays);
    EXPECT_EQ(recorder.recordedRays(), recorded.rays);

    ReplayStats replay = recorder.replay(2);
    EXPECT_EQ(replay.rays, recorded.rays);
    EXPECT_EQ(replay.hits, recorder.recordedHits());
    EXPECT_GT(replay.hits, 0u);
    // Camera rays went as packets, one per sample; bounce rays one at a time; shadow rays as
    // packets.
    EXPECT_EQ(replay.raysOf[size_t(TraversalCall::IntersectBatch)], recorded.samples);
    EXPECT_GT(replay.raysOf[size_t(TraversalCall::Intersect1)], 0u);
    EXPECT_GT(replay.raysOf[size_t(TraversalCall::OccludedBatch)], 0u);
    EXPECT_EQ(replay.raysOf[0] + replay.raysOf[size_t(TraversalCall::IntersectBatch)] +
                  replay.raysOf[2] + replay.raysOf[3],
              replay.rays);
}

}  // namespace
}  // namespace kiln
