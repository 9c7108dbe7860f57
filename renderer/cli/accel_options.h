// Command-line options that choose and configure an accelerator, shared by render, crosscheck and
// bench.
#pragma once

#include <memory>

#include "renderer/accel/accelerator.h"
#include "renderer/cli/cli_args.h"
#include "renderer/render_job.h"

namespace kiln {

// A brute-force render estimated to take longer than this is refused.
constexpr double kBruteForceLimitSeconds = 3600;

// Seconds a brute-force render of these options would take: rays (camera, then per vertex the
// light samples and the next bounce, up to four vertices) x primitives x the measured cost of a
// test, over the threads.
double bruteForceSeconds(const Scene& scene, const RenderJobOptions& render);

struct AcceleratorChoice {
    AcceleratorKind kind = AcceleratorKind::Embree;
    EmbreeOptions embree;
    ReferenceBvhOptions reference;

    void addOptions(ArgParser& parser, bool withKind);
    // With the render's options, a brute-force choice whose estimated time is over
    // kBruteForceLimitSeconds is refused (UsageError naming the estimate) before any work.
    std::unique_ptr<Accelerator> build(const Scene& scene,
                                       const RenderJobOptions* render = nullptr) const;
    // This choice with Embree's build kept to a render's -t (0: every core), at most the cores
    // there are. Embree holds the count as a TBB global_control, for the whole process, while the
    // accelerator lives.
    AcceleratorChoice withThreads(int threads) const;

    bool operator==(const AcceleratorChoice&) const = default;
};

// How many accelerators AcceleratorChoice::build has built in this process (kiln render-frames
// reports it beside sceneLoadCount()).
uint64_t acceleratorBuildCount();

}  // namespace kiln
