// kiln render's options and the steps around its RenderJob that every front end shares: the
// command line (cmd_render.cpp) and the Python module (python/) declare, check and apply the
// options, name the render in the EXR header and write the outputs through these functions, so
// the same options give the same image, the same metadata and the same messages.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "color/image_output.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/camera_options.h"
#include "renderer/cli/cli_args.h"
#include "renderer/cli/queue_output.h"
#include "renderer/cli/render_options.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {

enum class ProgressOutput { Bar, Json, None };  // --progress

template <>
struct EnumNames<ProgressOutput> {
    static constexpr std::pair<ProgressOutput, const char*> table[] = {
        {ProgressOutput::Bar, "bar"},
        {ProgressOutput::Json, "json"},
        {ProgressOutput::None, "none"}};
};

// Everything kiln render's command line says.
struct RenderCommand {
    RenderJobArgs job;
    AcceleratorChoice accel;
    LoadOptions load;
    CameraOptions camera;
    std::string output;         // base path, or the -f file
    std::string display, view;  // empty: the OCIO config's defaults
    std::string look;           // --look: an OCIO look applied before the view (empty: none)
    float exposure = 0;         // stops
    ExrOptions exr;
    bool transparent = false, json = false;
    ProgressOutput progress = ProgressOutput::Bar;
    std::vector<std::string> warnings;  // also in the --json result
    std::string colourConfig;           // the OCIO config in force
    DepthMode depth = DepthMode::Ray;
    bool heatMap = false, quiet = false, traversalFloor = false;
    bool denoise = false;  // --denoise: half-buffers kept, the beauty denoised (docs/denoise.md)
    uint32_t denoisedLight = 0;  // --denoise-aovs: light-path kinds denoised too (AovRequest bits)
    float aperture = -1, focus = -1;
    int debugX = -1, debugY = -1, debugSample = -1;
    // Long renders (docs/long-renders.md).
    double checkpointEvery = 0, timeLimit = 0;
    bool resume = false;
    // --no-final-checkpoint: a finished whole frame leaves no OUT.ckpt, none written at its end and
    // one written during it removed (a batch or farm frame whose checkpoint its caller removes).
    bool noFinalCheckpoint = false;
    int rangeStart = -1, rangeEnd = -1;  // --sample-range
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
    bool checkpoints() const {
        return checkpointEvery > 0 || timeLimit > 0 || resume || rangeStart >= 0;
    }
};

struct OutputPaths {
    std::string exr, preview, checkpoint;
};

// Every option of kiln render, in the groups and order of its --help.
void addRenderOptions(ArgParser& parser, RenderCommand& c);

// The job the options describe: the render region, the AOV request, the sample range, the
// compositing conventions. Throws UsageError.
RenderJobOptions renderJobOptions(const RenderCommand& c);

// Before any expensive work: the film and the EXR write fit the memory available. Throws
// UsageError saying how much they need.
void checkFilmFits(const RenderJobOptions& o, bool checkpoints);

// The OCIO config, display and view checked before any work; the defaults filled in. Throws
// UsageError.
void checkColour(RenderCommand& c);

// The camera options (--position ... --turntable/--frame) and the thin lens (-b, -d) applied to
// the loaded scene, whose storedBounds() are `stored` (found once per load: a pass over every
// vertex, a tenth of a 1M-triangle thumbnail frame). Throws UsageError on an impossible camera.
void applyCameraOptions(Scene& scene, const RenderCommand& c, const Bounds3& stored);

// A warning when the direct-light sampling cannot see the scene's only lights.
void warnHemisphereBlind(const RenderJob& job, const std::string& scenePath);

// Warnings for options that would do nothing in this render: adaptive sampling whose first test
// comes at or after the last sample, --denoise with fewer than two samples a pixel.
void warnIdleOptions(const RenderJob& job, const RenderCommand& c);

// What the EXR states about the scene (camera matrices, Cryptomatte manifests) and which kiln
// wrote it (Software).
void addSceneToOutputs(RenderCommand& c, const Scene& scene, const RenderJobOptions& options);

// OUT.exr, OUT.png (or the -f file and the EXR beside it) and OUT.ckpt. Throws UsageError when the
// output directory does not exist.
OutputPaths outputPaths(const RenderCommand& c, const std::string& scenePath);
// The same names, unchecked (a batch's outputs before their directories are made).
OutputPaths outputNames(const RenderCommand& c, const std::string& scenePath);

// The EXR header's kiln: attributes: the job's options and results, the scene, the AOV list, the
// display, the build.
Metadata renderMetadata(const RenderJob& job, const RenderCommand& c, const std::string& scenePath,
                        const RenderStats& stats, const Film& film);

// A --denoise render's denoised images (exr.denoised, exr.denoisedLayers) and the metadata
// entries that say so, as denoiseForOutputs makes them: made once where a caller needs them
// besides the files (the Python module's kiln.Image).
struct DenoisedFrame {
    ExrOptions exr;
    Metadata meta;
};
// The film's denoised frame for a render with --denoise (threads: the render's -t).
DenoisedFrame denoiseFrame(const Film& film, int threads);

// Whether the render writes OUT.samples.png: with -a, --noise-threshold or --heatmap.
bool writesHeatMap(const RenderCommand& c);

// Writes OUT.exr, OUT.png and, with -a, --noise-threshold or --heatmap, OUT.samples.png (its path
// in heatPath), each on its own: one failing write does not stop the others. Each failure's
// message goes to onError (default: logged as an error); returns how many failed. writes, when
// given, receives each file and how its write went. With --denoise, `denoised` (when given) is
// the film's denoised frame, else it is denoised here.
int writeOutputs(const RenderCommand& c, const OutputPaths& out, const Film& film,
                 const Metadata& meta, std::string& heatPath,
                 const std::function<void(const std::string&)>& onError = {},
                 std::vector<OutputWrite>* writes = nullptr,
                 const DenoisedFrame* denoised = nullptr);

}  // namespace kiln
