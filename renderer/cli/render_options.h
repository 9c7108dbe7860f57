// Option groups that several commands share, declared once: how a scene is loaded (--camera,
// --env) and what a render job does (size, samples, integrator, sampling, AOVs, plan).
#pragma once

#include <string>

#include "renderer/cli/cli_args.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {

// --camera file|framed, -e/--env MAP, --material-override, --texture-cache-mb,
// --env-rotate/strength.
void addLoadOptions(ArgParser& parser, LoadOptions& load);

// --output OUT, and -o: CS184's accumulate-bounces switch for a lone 0 or 1, else the output name.
void addOutputNameOptions(ArgParser& parser, std::string& output, PathOptions& path);

// --emitters lights|camera: emissive meshes as lights, or as the CS184 program (camera rays only).
void addEmitterOption(ArgParser& parser, LoadOptions& load, PathOptions& path);

// --exposure STOPS: the preview's light scaled by 2^STOPS.
void addExposureOption(ArgParser& parser, float& stops);

// --denoise-aovs LIST (kiln render, kiln denoise): the light-path kinds it names (AovRequest
// bits). Throws UsageError naming an unknown or non-light entry.
uint32_t parseDenoisedAovs(const std::string& list);

// A render job's options as given on the command line; finish() turns them into RenderJobOptions.
struct RenderJobArgs {
    RenderJobOptions job;
    std::string aovList = "default";
    double crop[4] = {0, 1, 0, 1};  // --crop X0 X1 Y0 Y1, fractions of the image

    // -r --crop -s -t --tile --seed -i -m -l -a -H --sampling --heuristic --rr --rr-continue
    // --bounce-only --microfacet --plan --aov
    void addOptions(ArgParser& parser);
    // The render region from --crop (pbrt's rule) and the AOV request. Throws UsageError.
    RenderJobOptions finish() const;
};

}  // namespace kiln
