// kiln render: option parsing, then one RenderJob, then the outputs (the steps the Python module
// shares are in render_command.h).
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#include "color/atomic_file.h"
#include "color/exr_threads.h"
#include "color/image_module.h"
#include "renderer/accel/recording_accelerator.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/output_check.h"
#include "renderer/cli/render_command.h"
#include "renderer/core/json.h"
#include "renderer/core/log.h"
#include "renderer/core/memory.h"
#include "renderer/farm/render_task.h"
#include "renderer/frame_probe.h"
#include "renderer/long_render.h"
#include "renderer/progress.h"

namespace kiln {
namespace {

// Signals only set flags: the render stops (or checkpoints) at the next pixel, and a signal that
// arrives while the outputs are written lets the writes finish.
extern "C" void onInterrupt(int) { renderCancelFlag().store(true); }
extern "C" void onCheckpointRequest(int) { checkpointRequestFlag().store(true); }

namespace fs = std::filesystem;

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Writability tried by creating a file (permission bits say nothing for root or read-only mounts),
// and no output's name taken by a directory, so a job fails before loading, not after rendering.
void checkOutputWritable(const RenderCommand& c, const OutputPaths& out) {
    std::vector<OutputWrite> outputs{{"exr", out.exr, ""}, {"preview", out.preview, ""}};
    if (c.checkpoints()) outputs.push_back({"checkpoint", out.checkpoint, ""});
    std::error_code ec;
    for (OutputWrite& o : outputs)
        if (fs::is_directory(o.path, ec)) throw OutputError({o.kind, o.path, "is a directory"});
    fs::path dir = fs::path(out.exr).parent_path();
    std::string probe = ((dir.empty() ? fs::path(".") : dir) / ".kiln-write-test-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0)
        throw UsageError(fmt::format("output directory '{}' is not writable: {}",
                                     dir.empty() ? "." : dir.string(), std::strerror(errno)));
    ::close(fd);
    ::unlink(probe.c_str());
    std::vector<std::string> paths;
    for (const OutputWrite& o : outputs) paths.push_back(o.path);
    checkOutputFiles(paths);  // names the file system refuses (too long with the temporary's)
}

void applyQueueOptions(const RenderCommand& c, RenderJobOptions& options) {
    options.settings.progress = !c.quiet && c.progress != ProgressOutput::None;
    // JSON progress includes the stage lines (load, build, ...), unless progress is off.
    Progress::setStyle(c.progress == ProgressOutput::Json && options.settings.progress
                           ? ProgressStyle::Json
                           : ProgressStyle::Text);
    // Machine output asked for: every message a JSON line too, so a queue parses all of stderr.
    if (c.json || c.progress == ProgressOutput::Json) setLogFormat(LogFormat::JsonLines);
}

struct RenderTimes {
    double load = 0, build = 0, write = 0;
};

int& rendersInProcess() {
    static int renders = 0;
    return renders;
}

// The --json result (docs/output.md): the exit code and its status, every output written and not.
Json renderResult(const RenderCommand& c, const Scene& scene,
                  const std::vector<OutputWrite>& writes, const RenderStats& stats,
                  const Film& film, const RenderTimes& times, int exitCode) {
    std::vector<std::string> warnings = scene.warnings;
    warnings.insert(warnings.end(), c.warnings.begin(), c.warnings.end());
    if (stats.nonFiniteSamples)
        warnings.push_back(std::to_string(stats.nonFiniteSamples) +
                           " non-finite samples were dropped");
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    Json result = {{"command", "render"},
                   {"status", exitStatus(exitCode)},
                   {"exit_code", exitCode},
                   {"scene", scene.sourcePath}};
    addOutputs(result, writes);
    result.update(Json{
        {"seconds",
         {{"load", times.load},
          {"build", times.build},
          {"render", stats.seconds},
          {"write", times.write}}},
        {"rays", stats.rays},
        {"samples", stats.samples},
        {"spp",
         film.width() > 0 ? double(stats.samples) / (double(film.width()) * film.height()) : 0.0},
        {"nonfinite_samples", stats.nonFiniteSamples},
        {"peak_memory_bytes", uint64_t(usage.ru_maxrss) * 1024},
        {"interrupted", stats.interrupted},
        {"process",  // more than one render when kiln render-frames ran it
         {{"renders", rendersInProcess()},
          {"scene_loads", sceneLoadCount()},
          {"accelerator_builds", acceleratorBuildCount()},
          {"scene_checksums", sceneChecksumCount()}}},
        {"time_limit_reached", stats.timeLimitReached},
        {"ocio_config", c.colourConfig},
        {"display", c.display},
        {"view", c.view},
        {"look", c.look},
        {"warnings", warnings}});
    return result;
}

int printDebugSample(const RenderJob& job, const RenderCommand& c) {
    if (c.debugX < 0 || c.debugSample < 0) throw UsageError("--pixel and --sample go together");
    RayCounter counter;
    SampleRecord r = job.traceSample(c.debugX, c.debugY, c.debugSample, counter);
    std::printf("pixel %d %d sample %d: L = %.9g %.9g %.9g (%s), %llu rays\n", c.debugX, c.debugY,
                c.debugSample, r.L.x, r.L.y, r.L.z, isFinite(r.L) ? "finite" : "NOT FINITE",
                (unsigned long long)counter.rays);
    std::printf("  emission %.9g direct %.9g indirect %.9g (luminance); depth %.9g\n",
                luminance(r.emission), luminance(r.direct), luminance(r.indirect), r.depth);
    return isFinite(r.L) ? 0 : 1;
}

// The render again, every traversal call recorded, then the recorded calls traced alone: the
// part of the render time no shading speed-up can remove.
void printTraversalFloor(const Accelerator& accel, const RenderJob& job, const RenderStats& first) {
    // The second render traces exactly the first one's rays (samples are deterministic), so what
    // recording needs is known before it starts: the rays plus an eighth for the call records and
    // the chunks' slack.
    uint64_t need = first.rays * sizeof(Ray) / 8 * 9, available = availableMemoryBytes();
    if (need > available)
        throw UsageError(fmt::format(
            "--traversal-floor: recording the render's {} rays needs {:.1f} MiB, {:.1f} MiB "
            "available (the image is written; fewer samples or a --crop fit)",
            first.rays, double(need) / (1 << 20), double(available) / (1 << 20)));
    RecordingAccelerator recorder(accel);
    RenderJob again(job, recorder);
    Film film = again.makeFilm();
    renderCancelFlag().store(false);
    RenderStats second = again.render(film);
    ReplayStats replay = recorder.replay(job.options().settings.threads);
    if (replay.rays != second.rays || replay.hits != recorder.recordedHits())
        throw std::logic_error("traversal floor: the replay traced other rays than the render");
    logInfo(
        "traversal floor: the render's {} rays traced again alone, in the same calls: {:.3f}s "
        "({:.2f} Mrays/s) against the render's {:.3f}s: traversal {:.0f} %, shading, sampling "
        "and film {:.0f} %",
        replay.rays, replay.seconds, double(replay.rays) / replay.seconds * 1e-6, first.seconds,
        100.0 * replay.seconds / first.seconds, 100.0 * (1.0 - replay.seconds / first.seconds));
    // Batched calls are 16-wide packets in Embree's default mode, loops of single rays otherwise.
    const char* kinds[4] = {"closest hit, one ray per call", "closest hit, batched",
                            "occlusion, one ray per call", "occlusion, batched"};
    for (size_t k = 0; k < 4; ++k)
        if (replay.raysOf[k])
            logInfo("  {:<32} {:>11} rays {:7.1f} ns per ray per thread", kinds[k],
                    replay.raysOf[k], replay.threadSeconds[k] / double(replay.raysOf[k]) * 1e9);
}

// SIGINT and SIGTERM stop the render at a pixel boundary, SIGUSR1 asks for a checkpoint; the
// handlers stay until the outputs are written. SA_RESTART: a signal does not fail a write.
struct SignalScope {
    struct sigaction previous[3]{};
    static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGUSR1};
    SignalScope() {
        renderCancelFlag().store(false);
        checkpointRequestFlag().store(false);
        for (int i = 0; i < 3; ++i) {
            struct sigaction act {};
            act.sa_handler = kSignals[i] == SIGUSR1 ? onCheckpointRequest : onInterrupt;
            sigemptyset(&act.sa_mask);
            act.sa_flags = SA_RESTART;
            sigaction(kSignals[i], &act, &previous[i]);
        }
    }
    ~SignalScope() {
        for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &previous[i], nullptr);
    }
};

void printSummary(const std::string& scenePath, const std::vector<OutputWrite>& writes,
                  const RenderStats& stats, double load, double build, double write) {
    double mrays = stats.seconds > 0 ? double(stats.rays) / stats.seconds * 1e-6 : 0.0;
    std::string written;  // the images that were written (a failed one has had its error line)
    for (const OutputWrite& w : writes)
        if (w.error.empty() && w.kind != "checkpoint")
            written += (written.empty() ? "" : ", ") + w.path;
    logInfo("{} -> {}", scenePath, written.empty() ? "no image written" : written);
    logInfo(
        "{} samples, {} rays, {:.2f} Mrays/s; time load {:.3f}s, build {:.3f}s, render {:.3f}s, "
        "write {:.3f}s",
        stats.samples, stats.rays, mrays, load, build, stats.seconds, write);
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    logInfo("peak resident memory {:.1f} MiB", double(usage.ru_maxrss) / 1024.0);
    if (stats.nonFiniteSamples) {
        logWarning("{} non-finite samples were dropped (not written into the image)",
                   stats.nonFiniteSamples);
        for (const BadSample& b : stats.firstBadSamples)
            logInfo("  replay with: kiln render {} ... --pixel {} {} --sample {}", scenePath, b.x,
                    b.y, b.sample);
    }
}

constexpr const char* kExitCodes =
    "\nexit status: 0 done; 1 failure (e.g. an output could not be written); 2 bad input; 3 "
    "--time-limit reached, OUT.ckpt and the image so far saved (--resume continues); 130 "
    "interrupted (SIGINT/SIGTERM), OUT.ckpt (with checkpoints on) and the image so far saved.\n"
    "With --checkpoint-every, --resume, --sample-range or --time-limit, OUT.ckpt is written at "
    "the end too (kiln merge combines such files), unless --no-final-checkpoint and the whole "
    "frame finished. See docs/long-renders.md.\n";

// Before any expensive work: the directory takes files, the outputs fit its free space, and the
// memory the EXR write needs (beside the film) is there.
void checkOutputsFit(const RenderCommand& c, const RenderJobOptions& o, const OutputPaths& out) {
    OutputSizes need = estimateOutputs(o, c.checkpoints());
    fs::path dir = fs::path(out.exr).parent_path();
    const std::vector<std::string> paths{out.exr, out.preview, out.checkpoint};
    const std::vector<int> removed = removeStaleTemporaries(paths);
    for (size_t i = 0; i < paths.size(); ++i)
        if (removed[i])
            logInfo("removed {} temporary file(s) of {} left by a killed kiln", removed[i],
                    paths[i]);
    try {
        checkOutputSpace(dir.empty() ? "." : dir.string(),
                         need.exr + need.preview + need.checkpoint);
    } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
    }
    checkFilmFits(o, c.checkpoints());
}

// The final checkpoint, after the images: a checkpoint that does not fit (a full disk) cannot cost
// a finished image. Its failure is a warning when the render is complete and its images were
// written (the checkpoint would only serve a later refinement); otherwise (a time limit, an
// interruption, a shard for kiln merge, an image not written) it is an error: returns 1 then.
int writeCheckpointAfterImages(RenderCommand& c, const RenderJob& job, const LongRenderOptions& lo,
                               LongRenderResult& r, const OutputPaths& out, int imageFailures,
                               std::vector<OutputWrite>& writes) {
    // The job's settings: the command's own hold no --crop region (renderJobOptions adds it).
    const bool shard = c.rangeStart >= 0 || job.options().settings.hasRegion();
    // --no-final-checkpoint: the caller removes a finished frame's checkpoint (0.7 GB at 1080p)
    // as soon as it is done; one stopped early or a shard's is what --resume or kiln merge reads.
    // One written during the render goes too: the flag is for callers that remove the frame's
    // checkpoint once it is done (it would spare a later refinement only the samples it holds).
    const bool stopped = r.stats.interrupted || r.stats.timeLimitReached;
    if (c.noFinalCheckpoint && imageFailures == 0 && r.stats.complete && !stopped && !shard) {
        std::error_code ec;
        if (!lo.checkpointPath.empty()) fs::remove(lo.checkpointPath, ec);
        return 0;
    }
    try {
        writeFinalCheckpoint(lo, r);
        if (!lo.checkpointPath.empty()) writes.push_back({"checkpoint", out.checkpoint, ""});
    } catch (const std::exception& e) {
        writes.push_back({"checkpoint", out.checkpoint, e.what()});
        if (imageFailures == 0 && r.stats.complete && !shard) {
            std::string text = fmt::format(
                "{} (the finished image is written; the checkpoint would only serve a later "
                "refinement with --resume)",
                e.what());
            logWarning("{}", text);
            c.warnings.push_back(text);
            return 0;
        }
        logError("{}", e.what());
        return 1;
    }
    if (r.checkpointBytes)
        logInfo("checkpoint {}: {:.1f} MiB written in {:.3f}s", out.checkpoint,
                double(r.checkpointBytes) / (1 << 20), r.checkpointSeconds);
    return 0;
}

// fingerprint: the checkpoint fingerprint (empty without checkpoints).
int renderLong(RenderCommand& c, const RenderJob& job, const Accelerator& accel,
               const std::string& scenePath, Fingerprint fingerprint, const OutputPaths& out,
               double loadTime, double buildTime) {
    LongRenderOptions lo;
    lo.checkpointPath = c.checkpoints() ? out.checkpoint : "";
    lo.checkpointEverySeconds = c.checkpointEvery;
    lo.timeLimitSeconds = c.timeLimit;
    lo.start = c.started;  // the limit counts from kiln's start: the queue slot's time
    lo.resume = c.resume;
    lo.fingerprint = std::move(fingerprint);
    lo.metadata = [&](const RenderStats& stats, const Film& film) {
        return renderMetadata(job, c, scenePath, stats, film);
    };
    lo.report = [](const std::string& text) { logInfo("{}", text); };
    LongRenderResult r = [&] {
        StageProgress stage("render", false);  // the render's own progress lines say it lives
        try {
            return renderLongFilm(job, lo);
        } catch (const CheckpointError& e) {
            throw UsageError(e.what());
        }
    }();
    auto t2 = std::chrono::steady_clock::now();
    std::string heatPath;
    std::vector<OutputWrite> writes;
    int failures = 0;
    {
        StageProgress stage("write");
        failures = writeOutputs(c, out, r.film,
                                r.totals.metadata.empty()
                                    ? renderMetadata(job, c, scenePath, r.stats, r.film)
                                    : r.totals.metadata,
                                heatPath, {}, &writes);
        failures += writeCheckpointAfterImages(c, job, lo, r, out, failures, writes);
    }
    double writeTime = seconds(t2);
    printSummary(scenePath, writes, r.stats, loadTime, buildTime, writeTime);
    if (job.guided())
        logInfo("path guiding {}; trained in {:.3f}s (counted in the render time)",
                job.guidingText(), job.guideTrainingSeconds());
    const bool stopped = r.stats.interrupted || r.stats.timeLimitReached;
    int code = failures              ? 1
               : !stopped            ? 0
               : r.stats.interrupted ? kExitInterrupted
                                     : kExitTimeLimit;
    if (code != 0 && code != 1)
        logInfo("{}: wrote {}the image so far (per-pixel sample counts in the EXR)",
                r.stats.interrupted ? "interrupted" : "time limit reached",
                lo.checkpointPath.empty() ? "" : out.checkpoint + " and ");
    if (code == 0 && c.traversalFloor) printTraversalFloor(accel, job, r.stats);
    if (c.json)
        printResult(renderResult(c, job.scene(), writes, r.stats, r.film,
                                 {loadTime, buildTime, writeTime}, code));
    return code;
}

// The one scene file among the positional arguments; anything more is not an option.
void checkOneScene(const std::vector<std::string>& pos) {
    if (pos.empty()) throw UsageError("needs exactly one scene file (see 'kiln render --help')");
    if (pos.size() > 1)
        throw UsageError("needs exactly one scene file; '" + pos[1] +
                         "' is not an option (see 'kiln render --help')");
}

// The checks of the options alone, before anything is opened: the job's options (long-render and
// compositing combinations), the camera override and the debug pair.
RenderJobOptions checkedJobOptions(const RenderCommand& c) {
    RenderJobOptions jobOptions = renderJobOptions(c);
    c.camera.check();
    if ((c.debugX >= 0) != (c.debugSample >= 0))
        throw UsageError("--pixel and --sample go together");
    const RenderSettings& s = jobOptions.settings;
    if (c.debugX >= s.width || c.debugY >= s.height)
        throw UsageError("--pixel is outside the " + std::to_string(s.width) + "x" +
                         std::to_string(s.height) + " image");
    return jobOptions;
}

// The scene and accelerator of the last render of this process, kept for the next render that
// loads the same file with the same load options (kiln render-frames): only its camera differs,
// which each render sets afresh from the camera as loaded. The accelerator is kept too when the
// accelerator options and -t (Embree's build keeps to the threads of the render that made it) are
// the same.
struct LoadedScene {
    std::string path;
    LoadOptions load;
    AcceleratorChoice choice;
    std::unique_ptr<Scene> scene;
    Camera camera;   // as loaded, before any render's camera options
    Bounds3 bounds;  // the scene's storedBounds(), for the camera options
    std::unique_ptr<Accelerator> accel;
    // The scene's files as a checkpoint fingerprint names them, read at the first render with
    // checkpoints: every render of this load shares them (the data rendered is this load's). The
    // scene file and --env map (top) are read before the load when a resume is checked then.
    std::optional<SceneFileIdentity> top, files;

    bool holdsScene(const std::string& scenePath, const RenderCommand& c) const {
        return scene && scenePath == path && c.load == load;
    }
    // Brute force is built for each render: its refusal depends on the render's size and samples.
    bool holdsAccelerator(const std::string& scenePath, const RenderCommand& c) const {
        return accel && holdsScene(scenePath, c) && c.accel == choice &&
               choice.kind != AcceleratorKind::BruteForce;
    }
    // Forgets the scene held for the one this file and these options will load.
    void expect(const std::string& scenePath, const LoadOptions& options) {
        accel.reset();  // the accelerator before the scene it points into
        scene.reset();
        top.reset();
        files.reset();
        path = scenePath, load = options;
    }
    const SceneFileIdentity& topFiles() {
        if (!top) top = topFileIdentity(path, load);
        return *top;
    }
    const SceneFileIdentity& fileIdentity() {
        if (!files) files = withInputIdentities(topFiles(), path, load, *scene);
        return *files;
    }
};

// --resume against a checkpoint of another scene file or other options is refused here, before
// the load, the build and the probe (at 100M triangles, a minute); what only the loaded scene
// decides (the camera, the plan, the other files) is checked after (resumeFilm).
void refuseResumeBeforeLoad(const RenderCommand& c, const RenderJobOptions& options,
                            const OutputPaths& out, LoadedScene& loaded) {
    if (std::error_code ec; !c.resume || !fs::exists(out.checkpoint, ec)) return;
    const SceneFileIdentity* files = nullptr;
    try {
        files = &loaded.topFiles();
    } catch (const std::runtime_error&) {
        return;  // an unreadable scene or map, or a folder: the load names it
    }
    try {
        kiln::checkResumeBeforeLoad(out.checkpoint, options.settings,
                                    fingerprintBeforeLoad(options, *files, c.load));
    } catch (const CheckpointError& e) {
        throw UsageError(e.what());
    }
}

// kiln render's steps for one command line (SCENE and options): the checks, the scene and its
// accelerator (those `loaded` holds when it holds them for this render), the render and its
// outputs. With `output` (kiln render-frames) the command must name its output base with -o, which
// `output` receives.
int renderFrame(const std::vector<std::string>& args, LoadedScene& loaded,
                std::string* output = nullptr) {
    RenderCommand c;
    ArgParser parser("render", "SCENE [options]   (writes OUT.exr and OUT.png)");
    addRenderOptions(parser, c);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        if (output) throw UsageError("--help is not a render option");
        std::fputs(parser.helpText().c_str(), stdout);
        std::fputs(kExitCodes, stdout);
        return 0;
    }
    checkOneScene(pos);
    if (output && (*output = c.output).empty())
        throw UsageError("every render of kiln render-frames needs -o OUT (it writes OUT.done)");
    const std::string& scenePath = pos[0];
    RenderJobOptions jobOptions = checkedJobOptions(c);
    // OpenEXR's threads too (an environment map read at the load, the EXR written at the end),
    // before the image module loads: OpenImageIO keeps the count it finds.
    setExrThreads(c.job.job.settings.threads);
    applyQueueOptions(c, jobOptions);
    checkColour(c);
    OutputPaths out = outputPaths(c, scenePath);
    // OpenImageIO's writers, for a heat map or a preview in another format than PNG (kiln writes
    // the EXR and a PNG itself), loaded now: a missing module is an error before any work. A
    // texture or a map loads it when the scene is read.
    if (writesHeatMap(c) || !writesPngPreview(out.preview)) requireImageModule();
    checkOutputWritable(c, out);
    checkOutputsFit(c, jobOptions, out);

    // Embree's build on the render's threads too: a farm task given 4 cores of a node keeps to
    // them from the first moment.
    c.accel = c.accel.withThreads(c.job.job.settings.threads);
    const bool sceneReused = loaded.holdsScene(scenePath, c);
    const bool reused = loaded.holdsAccelerator(scenePath, c);
    if (!sceneReused) loaded.expect(scenePath, c.load);
    // Not for a debug sample, which writes no checkpoint.
    const bool debugSample = c.debugX >= 0 || c.debugSample >= 0;
    if (!debugSample) refuseResumeBeforeLoad(c, jobOptions, out, loaded);
    double loadTime = 0, buildTime = 0;
    if (!sceneReused) {
        auto t0 = std::chrono::steady_clock::now();
        loaded.scene = std::make_unique<Scene>([&] {
            StageProgress stage("load");
            return loadScene(scenePath, c.load);
        }());
        loadTime = seconds(t0);
        loaded.camera = loaded.scene->camera;
        loaded.bounds = loaded.scene->storedBounds();
        for (const std::string& w : loaded.scene->warnings) logWarning("{}: {}", scenePath, w);
    }
    Scene& scene = *loaded.scene;
    scene.camera = loaded.camera;
    applyCameraOptions(scene, c, loaded.bounds);
    if (!reused) {
        loaded.accel.reset();  // its memory, and its hold on the threads, before the next build
        auto t1 = std::chrono::steady_clock::now();
        loaded.accel = [&] {
            StageProgress stage("build");
            return c.accel.build(scene, &jobOptions);
        }();
        buildTime = seconds(t1);
        loaded.choice = c.accel;
    }
    // Read here, once per load, so the line below counts this render's read.
    const SceneFileIdentity* files =
        c.checkpoints() && !debugSample ? &loaded.fileIdentity() : nullptr;
    if (++rendersInProcess() > 1)
        logInfo(
            "this process: {} renders, {} scene loads, {} accelerator builds, {} scene "
            "checksums{}",
            rendersInProcess(), sceneLoadCount(), acceleratorBuildCount(), sceneChecksumCount(),
            reused        ? " (this render reuses the scene and accelerator of the one before)"
            : sceneReused ? " (this render reuses the scene of the one before)"
                          : "");
    RenderJob job = [&] {
        StageProgress stage("plan");
        return RenderJob(scene, *loaded.accel, jobOptions);
    }();
    warnHemisphereBlind(job, scenePath);
    warnIdleOptions(job, c);
    if (debugSample) return printDebugSample(job, c);
    // What the camera will see decides the black-image warning (a few thousand samples).
    if (std::optional<std::string> black = blackImageWarning(probeFrame(job), c.exposure)) {
        logWarning("{}: {}", scenePath, *black);
        c.warnings.push_back(*black);
    }

    addSceneToOutputs(c, scene, jobOptions);
    Fingerprint fingerprint;
    if (files) fingerprint = checkpointFingerprint(job, *files, c.load);
    return renderLong(c, job, *loaded.accel, scenePath, std::move(fingerprint), out, loadTime,
                      buildTime);
}

constexpr const char* kRenderFramesUsage =
    "usage: kiln render-frames SCENE [render options] -o OUT [--then SCENE [render options] -o "
    "OUT]...\n"
    "Renders one kiln render command line after another in this process; a render that loads the "
    "same scene with the same load and accelerator options as the one before (frames that differ "
    "only in camera) reuses its scene and accelerator. Writes OUT.done (the command line) after "
    "each finished render and stops at the first that does not exit 0, with its exit status. "
    "kiln batch and farm shards run their frames of one scene this way (docs/farm.md).\n";

}  // namespace

namespace {

// Every render's command line checked before the first renders (a bad last one failed after the
// others had rendered), and no two writing one output (the second overwrote the first).
void checkEveryFrame(const std::vector<std::vector<std::string>>& frames) {
    std::map<std::string, size_t> outputs;
    for (size_t i = 0; i < frames.size(); ++i) {
        CheckedRender render;
        try {
            render = checkRenderArguments(frames[i]);
            if (!render.outputGiven)
                throw UsageError(
                    "every render of kiln render-frames needs -o OUT (it writes "
                    "OUT.done)");
            checkOutputBase(render.files[0]);  // its directory exists (a batch has made it)
        } catch (const UsageError& e) {
            throw UsageError(fmt::format("render {} of {}: {}", i + 1, frames.size(), e.what()));
        }
        for (const std::string& file : render.files) {
            std::error_code ec;
            const std::string key = fs::absolute(file, ec).lexically_normal().string();
            if (auto [at, fresh] = outputs.emplace(key, i); !fresh && at->second != i)
                throw UsageError(fmt::format("renders {} and {} of {} both write {}",
                                             at->second + 1, i + 1, frames.size(), file));
        }
    }
}

}  // namespace

CheckedRender checkRenderArguments(const std::vector<std::string>& args) {
    RenderCommand c;
    ArgParser parser("render", "SCENE [options]");
    addRenderOptions(parser, c);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) throw UsageError("--help is not a render option");
    checkOneScene(pos);
    checkedJobOptions(c);
    try {
        checkColorConfig(c.display, c.view, c.look);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    const OutputPaths out = outputNames(c, pos[0]);
    CheckedRender checked{!c.output.empty(), {out.exr, out.preview}};
    if (writesHeatMap(c))
        checked.files.push_back(fs::path(out.exr).replace_extension(".samples.png").string());
    return checked;
}

int runRender(const std::vector<std::string>& args) {
    // From the start a signal stops the work and saves what it has (a farm may send SIGTERM or
    // SIGUSR1 while the scene loads).
    SignalScope signals;
    LoadedScene loaded;
    return renderFrame(args, loaded);
}

int runRenderFrames(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help" || args[0] == "-h") {
        std::fputs(kRenderFramesUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    std::vector<std::vector<std::string>> frames{{}};
    for (const std::string& a : args)
        if (a == "--then")
            frames.emplace_back();
        else
            frames.back().push_back(a);
    checkEveryFrame(frames);
    SignalScope signals;
    LoadedScene loaded;
    for (const std::vector<std::string>& frame : frames) {
        if (renderCancelFlag().load()) return kExitInterrupted;  // signalled between two renders
        std::string output;
        if (int code = renderFrame(frame, loaded, &output)) return code;
        std::vector<std::string> command{"render"};
        command.insert(command.end(), frame.begin(), frame.end());
        farm::markComplete(output, command);
    }
    return 0;
}

}  // namespace kiln
