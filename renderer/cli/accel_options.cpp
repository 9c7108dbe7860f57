#include "renderer/cli/accel_options.h"

#include <fmt/format.h>
#include <tbb/info.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>

#include "renderer/accel/brute_force.h"

namespace kiln {
namespace {

std::atomic<uint64_t>& buildCounter() {
    static std::atomic<uint64_t> count{0};
    return count;
}

}  // namespace

uint64_t acceleratorBuildCount() { return buildCounter().load(); }

void AcceleratorChoice::addOptions(ArgParser& parser, bool withKind) {
    OptionGroup group(parser, "Accelerator");
    if (withKind)
        parser.enumOption(
            "accel",
            "traversal: Embree (default), the reference BVH, or brute force (every ray against "
            "every primitive: CS184's timing without a BVH; refused when estimated over an hour)",
            kind);
    parser.enumOption("embree-quality", "Embree BVH build quality (default medium)",
                      embree.quality);
    parser.option("no-robust", "", 0, "",
                  "drop RTC_SCENE_FLAG_ROBUST (faster, may leak through shared edges)",
                  [this](const std::vector<std::string>&) { embree.robust = false; });
    parser.option("watertight", "", 0, "",
                  "Embree traverses, kiln's double-precision test intersects triangles: no leaks "
                  "at shared vertices either (slower)",
                  [this](const std::vector<std::string>&) { embree.watertight = true; });
    parser.option("compact", "", 0, "", "RTC_SCENE_FLAG_COMPACT: smaller Embree BVH",
                  [this](const std::vector<std::string>&) { embree.compact = true; });
    parser.enumOption("bvh-split", "reference BVH split rule (default sah)", reference.split);
    parser.intOption("bvh-leaf", "", "reference BVH maximum leaf size (default 4)",
                     reference.maxLeafSize, 1, 255);
}

double bruteForceSeconds(const Scene& scene, const RenderJobOptions& render) {
    const RenderSettings& s = render.settings;
    double pixels = double(s.filmWidth()) * double(s.filmHeight());
    double vertices = std::min(render.path.maxDepth, 4);
    double rays = pixels * s.spp * (1 + vertices * (std::max(1, render.path.lightSamples) + 1));
    int threads =
        s.threads > 0 ? s.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    return rays * double(bruteForcePrimitiveCount(scene)) * kBruteForceNsPerTest * 1e-9 / threads;
}

AcceleratorChoice AcceleratorChoice::withThreads(int threads) const {
    AcceleratorChoice c = *this;
    c.embree.threads = threads > 0 ? std::min(threads, tbb::info::default_concurrency()) : 0;
    return c;
}

std::unique_ptr<Accelerator> AcceleratorChoice::build(const Scene& scene,
                                                      const RenderJobOptions* render) const {
    ++buildCounter();
    if (kind == AcceleratorKind::BruteForce) {
        double estimate = render ? bruteForceSeconds(scene, *render) : 0;
        if (estimate > kBruteForceLimitSeconds)
            throw UsageError(fmt::format(
                "--accel brute: {} primitives at this size would take about {:.1f} hours (limit "
                "{:.0f} minutes); use a smaller -r/-s or the BVH",
                bruteForcePrimitiveCount(scene), estimate / 3600, kBruteForceLimitSeconds / 60));
        return makeBruteForceAccelerator(scene);
    }
    if (kind == AcceleratorKind::Reference) return makeReferenceAccelerator(scene, reference);
    return makeEmbreeAccelerator(scene, embree);
}

}  // namespace kiln
