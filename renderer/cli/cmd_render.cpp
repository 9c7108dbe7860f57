// kiln render: option parsing, then one RenderJob, then the outputs.
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "color/atomic_file.h"
#include "color/image_output.h"
#include "renderer/accel/recording_accelerator.h"
#include "renderer/build_info.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/camera_options.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/render_options.h"
#include "renderer/core/json.h"
#include "renderer/core/log.h"
#include "renderer/core/memory.h"
#include "renderer/exr_scene.h"
#include "renderer/frame_probe.h"
#include "renderer/long_render.h"
#include "renderer/progress.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {
enum class ProgressOutput { Bar, Json, None };  // --progress
}  // namespace

template <>
struct EnumNames<ProgressOutput> {
    static constexpr std::pair<ProgressOutput, const char*> table[] = {
        {ProgressOutput::Bar, "bar"},
        {ProgressOutput::Json, "json"},
        {ProgressOutput::None, "none"}};
};

namespace {

// Signals only set flags: the render stops (or checkpoints) at the next pixel, and a signal that
// arrives while the outputs are written lets the writes finish.
extern "C" void onInterrupt(int) { renderCancelFlag().store(true); }
extern "C" void onCheckpointRequest(int) { checkpointRequestFlag().store(true); }

namespace fs = std::filesystem;

struct RenderCommand {
    RenderJobArgs job;
    AcceleratorChoice accel;
    LoadOptions load;
    CameraOptions camera;
    std::string output;         // base path, or the -f file
    std::string display, view;  // empty: the OCIO config's defaults
    float exposure = 0;         // stops
    ExrOptions exr;
    bool transparent = false, json = false;
    ProgressOutput progress = ProgressOutput::Bar;
    std::vector<std::string> warnings;  // also in the --json result
    std::string colourConfig;           // the OCIO config in force
    DepthMode depth = DepthMode::Ray;
    bool heatMap = false, quiet = false, traversalFloor = false;
    float aperture = -1, focus = -1;
    int debugX = -1, debugY = -1, debugSample = -1;
    // Long renders (docs/long-renders.md).
    double checkpointEvery = 0, timeLimit = 0;
    bool resume = false;
    int rangeStart = -1, rangeEnd = -1;  // --sample-range
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
    bool checkpoints() const {
        return checkpointEvery > 0 || timeLimit > 0 || resume || rangeStart >= 0;
    }
};

// Exit codes besides 0 (done), 1 (failure, e.g. a write) and 2 (bad input).
constexpr int kExitTimeLimit = 3;      // --time-limit reached: checkpoint saved, --resume goes on
constexpr int kExitInterrupted = 130;  // SIGINT/SIGTERM: checkpoint (if any) and image saved

struct OutputPaths {
    std::string exr, preview, checkpoint;
};

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void addCameraOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Camera");
    parser.option("aperture", "b", 1, "R",
                  "thin-lens aperture radius in scene units, CS184's -b (default 0: pinhole)",
                  [&c](const std::vector<std::string>& v) {
                      c.aperture = float(ArgParser::toDouble("--aperture", v[0]));
                      if (c.aperture < 0) throw UsageError("--aperture must be >= 0");
                  });
    parser.option("focus", "d", 1, "D",
                  "thin-lens focal distance, CS184's -d (default: distance to the scene centre)",
                  [&c](const std::vector<std::string>& v) {
                      c.focus = float(ArgParser::toDouble("--focus", v[0]));
                      if (!(c.focus > 0)) throw UsageError("--focus must be > 0");
                  });
}

void addOutputOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Output");
    addOutputNameOptions(parser, c.output, c.job.job.path);
    parser.option("file", "f", 1, "OUT.png", "CS184 form: preview file; the EXR goes beside it",
                  [&c](const std::vector<std::string>& v) { c.output = v[0]; });
    parser.option("display", "", 1, "NAME",
                  "OCIO display for the preview (default: the config's default display)",
                  [&c](const std::vector<std::string>& v) { c.display = v[0]; });
    parser.option("view", "", 1, "NAME",
                  "OCIO view for the preview (default: the display's default view; CS184: the "
                  "course's display)",
                  [&c](const std::vector<std::string>& v) { c.view = v[0]; });
    addExposureOption(parser, c.exposure);
    parser.flag("half", "", "write colour layers as half floats (data layers stay float)",
                c.exr.half);
    parser.flag("heatmap", "",
                "also write OUT.samples.png, the per-pixel sample counts as a heat map "
                "(always with -a)",
                c.heatMap);
}

void addLongRenderOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Long renders");
    auto seconds = [](const std::string& name, const std::string& text) {
        double v = ArgParser::toDouble(name, text);
        if (!(v > 0 && v < 1e9)) throw UsageError(name + " takes seconds > 0, got '" + text + "'");
        return v;
    };
    parser.option("checkpoint-every", "", 1, "SECONDS",
                  "write OUT.ckpt (the exact film, atomically) every SECONDS and on SIGINT, "
                  "SIGTERM, SIGUSR1",
                  [&c, seconds](const std::vector<std::string>& v) {
                      c.checkpointEvery = seconds("--checkpoint-every", v[0]);
                  });
    parser.flag("resume", "",
                "continue from OUT.ckpt (refused if it belongs to another scene, settings or "
                "kiln version); without OUT.ckpt, start from scratch. A larger -s refines",
                c.resume);
    parser.option("sample-range", "", 2, "A B",
                  "render samples [A, B) of every pixel (a shard for kiln merge); B is the spp",
                  [&c](const std::vector<std::string>& v) {
                      c.rangeStart = ArgParser::toInt("--sample-range", v[0], 0, (1 << 20) - 1);
                      c.rangeEnd = ArgParser::toInt("--sample-range", v[1], 1, 1 << 20);
                      if (c.rangeEnd <= c.rangeStart)
                          throw UsageError("--sample-range takes A B with A < B");
                  });
    parser.option("time-limit", "", 1, "SECONDS",
                  "stop at a pixel boundary SECONDS after start, write OUT.ckpt and the image so "
                  "far, exit 3 (--resume continues)",
                  [&c, seconds](const std::vector<std::string>& v) {
                      c.timeLimit = seconds("--time-limit", v[0]);
                  });
}

void addCompressionOption(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Output");
    parser.enumOption("compression",
                      "EXR compression (default zip; pxr24, b44, b44a, dwaa, dwab are lossy)",
                      c.exr.compression);
}

// Alpha and Z conventions of the EXR (see docs/output.md).
void addCompositingOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Output");
    parser.flag("transparent", "",
                "transparent background (Cycles' Film > Transparent): background seen directly "
                "leaves the image, alpha counts non-emitting surfaces only",
                c.transparent);
    parser.enumOption("depth",
                      "what Z holds: distance along the camera ray (default) or camera-space z",
                      c.depth);
}

// Writability tried by creating a file (permission bits say nothing for root or read-only mounts),
// so a job fails before loading, not after rendering.
void checkOutputWritable(const OutputPaths& out) {
    fs::path dir = fs::path(out.exr).parent_path();
    std::string probe = ((dir.empty() ? fs::path(".") : dir) / ".kiln-write-test-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0)
        throw UsageError(fmt::format("output directory '{}' is not writable: {}",
                                     dir.empty() ? "." : dir.string(), std::strerror(errno)));
    ::close(fd);
    ::unlink(probe.c_str());
}

void applyCompositingOptions(const RenderCommand& c, RenderJobOptions& options) {
    options.aovs.transparent = c.transparent;
    options.aovs.depth = c.depth;
}

// The OCIO config, display and view checked before any work; the defaults filled in.
void checkColour(RenderCommand& c) {
    try {
        ColorSetup setup = checkColorConfig(c.display, c.view);
        c.display = setup.display, c.view = setup.view, c.colourConfig = setup.configPath;
        c.exr.colorSpace = setup.sceneLinear;
        for (const std::string& w : setup.warnings) logWarning("{}", w);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

// What a job queue drives: one JSON result on stdout, progress as JSON lines on stderr.
void addQueueOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Messages");
    parser.flag("quiet", "q", "no progress bar", c.quiet);
    parser.flag("json", "",
                "print one JSON result on stdout: outputs, times, rays, samples, peak memory, "
                "warnings (docs/output.md); messages on stderr become JSON lines",
                c.json);
    parser.enumOption("progress",
                      "progress on stderr: a bar (plain lines when not a terminal), JSON lines "
                      "(the messages too), or none (as -q)",
                      c.progress);
}

void applyQueueOptions(const RenderCommand& c, RenderJobOptions& options) {
    options.settings.progress = !c.quiet && c.progress != ProgressOutput::None;
    Progress::setStyle(c.progress == ProgressOutput::Json ? ProgressStyle::Json
                                                          : ProgressStyle::Text);
    // Machine output asked for: every message a JSON line too, so a queue parses all of stderr.
    if (c.json || c.progress == ProgressOutput::Json) setLogFormat(LogFormat::JsonLines);
}

// Which kiln wrote the file: the libraries as kiln:libraries (the commit goes in Software).
void addBuildToMetadata(Metadata& meta) {
    meta["libraries"] = libraryVersions();
    meta["ocio_config"] = colorConfigPath();
}

struct RenderTimes {
    double load = 0, build = 0, write = 0;
};

void printJsonResult(const RenderCommand& c, const Scene& scene, const OutputPaths& out,
                     const std::string& heat, const RenderStats& stats, const Film& film,
                     const RenderTimes& times) {
    std::vector<std::string> warnings = scene.warnings;
    warnings.insert(warnings.end(), c.warnings.begin(), c.warnings.end());
    if (stats.nonFiniteSamples)
        warnings.push_back(std::to_string(stats.nonFiniteSamples) +
                           " non-finite samples were dropped");
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    Json outputs = {{"exr", out.exr}, {"preview", out.preview}};
    if (!heat.empty()) outputs["heatmap"] = heat;
    Json result = {
        {"scene", scene.sourcePath},
        {"outputs", outputs},
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
        {"ocio_config", c.colourConfig},
        {"display", c.display},
        {"view", c.view},
        {"warnings", warnings}};
    std::puts(jsonText(result).c_str());
}

void addDebugOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Debug");
    parser.option("pixel", "", 2, "X Y",
                  "debug: trace only this pixel (with --sample) and print what it returns",
                  [&c](const std::vector<std::string>& v) {
                      c.debugX = ArgParser::toInt("--pixel", v[0], 0, 1 << 20);
                      c.debugY = ArgParser::toInt("--pixel", v[1], 0, 1 << 20);
                  });
    parser.intOption("sample", "", "debug: the sample index to replay with --pixel", c.debugSample,
                     0, 1 << 30);
    parser.flag("traversal-floor", "",
                "benchmark: after the render, render again recording every ray, trace the "
                "recorded rays alone in the same calls, and print how much of the render time "
                "traversal is (needs 32 bytes of memory per ray)",
                c.traversalFloor);
}

OutputPaths outputPaths(const RenderCommand& c, const std::string& scenePath) {
    std::string base = c.output.empty() ? fs::path(scenePath).stem().string() : c.output;
    std::string ext = fs::path(base).extension().string();
    OutputPaths out{base + ".exr", base + ".png", ""};
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg")
        out = {fs::path(base).replace_extension(".exr").string(), base, ""};
    else if (ext == ".exr")
        out = {base, fs::path(base).replace_extension(".png").string(), ""};
    out.checkpoint = fs::path(out.exr).replace_extension(".ckpt").string();
    fs::path dir = fs::path(out.exr).parent_path();
    if (!dir.empty() && !fs::is_directory(dir))
        throw UsageError("output directory '" + dir.string() + "' does not exist");
    return out;
}

void applyThinLens(Scene& scene, const RenderCommand& c) {
    if (c.aperture <= 0) return;
    scene.camera.apertureRadius = c.aperture;
    scene.camera.focalDistance =
        c.focus > 0 ? c.focus
                    : std::max(1e-6f, dot(scene.storedBounds().centroid() - scene.camera.position,
                                          scene.camera.forward));
}

int printDebugSample(const RenderJob& job, const RenderCommand& c) {
    const RenderSettings& s = job.options().settings;
    if (c.debugX < 0 || c.debugSample < 0) throw UsageError("--pixel and --sample go together");
    if (c.debugX >= s.width || c.debugY >= s.height)
        throw UsageError("--pixel is outside the " + std::to_string(s.width) + "x" +
                         std::to_string(s.height) + " image");
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

void warnHemisphereBlind(const RenderJob& job, const std::string& scenePath) {
    const RenderJobOptions& o = job.options();
    const bool blind =
        o.path.sampling == DirectSampling::Hemisphere || o.path.sampling == DirectSampling::Bsdf;
    if (job.plan().deltaLightsOnly && blind && o.integrator == IntegratorKind::Path)
        logWarning(
            "{}: {} sampling cannot see point, spot or directional lights, the only lights here: "
            "the image will be black but for emitters",
            scenePath, toString(o.path.sampling));
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

void printSummary(const std::string& scenePath, const OutputPaths& out, const std::string& heat,
                  const RenderStats& stats, double load, double build, double write) {
    double mrays = stats.seconds > 0 ? double(stats.rays) / stats.seconds * 1e-6 : 0.0;
    logInfo("{} -> {}, {}{}{}", scenePath, out.exr, out.preview, heat.empty() ? "" : ", ", heat);
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
    "the end too (kiln merge combines such files). See docs/long-renders.md.\n";

void applyLongRenderOptions(const RenderCommand& c, RenderJobOptions& o) {
    RenderSettings& s = o.settings;
    if (c.rangeStart >= 0) s.sampleStart = c.rangeStart, s.spp = c.rangeEnd;
    if (s.sampleStart > 0 && s.adaptiveStep() > 0)
        throw UsageError(
            "--sample-range must start at 0 with -a or --noise-threshold: adaptive sampling "
            "decides from the samples before");
}

// Before any expensive work: the directory takes files, the outputs fit its free space, and the
// memory the EXR write needs (beside the film) is there.
void checkOutputsFit(const RenderCommand& c, const RenderJobOptions& o, const OutputPaths& out) {
    OutputSizes need = estimateOutputs(o, c.checkpoints());
    fs::path dir = fs::path(out.exr).parent_path();
    for (const std::string& path : {out.exr, out.preview, out.checkpoint})
        if (int n = removeStaleTemporaries(path))
            logInfo("removed {} temporary file(s) of {} left by a killed kiln", n, path);
    try {
        checkOutputSpace(dir.empty() ? "." : dir.string(),
                         need.exr + need.preview + need.checkpoint);
    } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
    }
    uint64_t memory = need.film + need.writeMemory, available = availableMemoryBytes();
    if (memory > available)
        throw UsageError("the film and the EXR write need " + std::to_string(memory >> 20) +
                         " MiB, " + std::to_string(available >> 20) +
                         " MiB available (a smaller -r, --crop or fewer --aov fit)");
}

// Each output written and reported on its own: one failing write does not stop the others.
int writeOutputs(const RenderCommand& c, const OutputPaths& out, const Film& film,
                 const Metadata& meta, std::string& heatPath) {
    int failures = 0;
    auto attempt = [&failures](auto&& write) {
        try {
            write();
        } catch (const std::exception& e) {
            logError("{}", e.what());
            ++failures;
        }
    };
    attempt([&] { writeExr(out.exr, film, meta, c.exr); });
    attempt([&] { writePreview(out.preview, film, c.display, c.view, c.exposure); });
    if (c.heatMap || c.job.job.settings.adaptiveStep() > 0) {
        heatPath = fs::path(out.exr).replace_extension(".samples.png").string();
        attempt([&] { writeSampleHeatMap(heatPath, film); });
    }
    return failures;
}

Metadata renderMetadata(const RenderJob& job, const RenderCommand& c, const std::string& scenePath,
                        const RenderStats& stats, const Film& film) {
    Metadata meta = job.metadata(stats, film);
    meta["scene"] = scenePath;
    meta["aovs"] = c.job.aovList;
    meta["display"] = c.display;
    meta["view"] = c.view;
    meta["exposure"] = std::to_string(c.exposure);
    addBuildToMetadata(meta);
    // For kiln merge, which writes the EXR the way this render would.
    meta["exr_storage"] =
        std::string(c.exr.half ? "half " : "float ") + toString(c.exr.compression);
    return meta;
}

// The final checkpoint, after the images: a checkpoint that does not fit (a full disk) cannot cost
// a finished image. Its failure is a warning when the render is complete and its images were
// written (the checkpoint would only serve a later refinement); otherwise (a time limit, an
// interruption, a shard for kiln merge, an image not written) it is an error: returns 1 then.
int writeCheckpointAfterImages(RenderCommand& c, const LongRenderOptions& lo, LongRenderResult& r,
                               const OutputPaths& out, int imageFailures) {
    try {
        writeFinalCheckpoint(lo, r);
    } catch (const std::exception& e) {
        const RenderSettings& s = c.job.job.settings;
        const bool shard = c.rangeStart >= 0 || s.hasRegion();
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

int renderLong(RenderCommand& c, const RenderJob& job, const std::unique_ptr<Accelerator>& accel,
               const std::string& scenePath, const OutputPaths& out, double loadTime,
               double buildTime) {
    LongRenderOptions lo;
    lo.checkpointPath = c.checkpoints() ? out.checkpoint : "";
    lo.checkpointEverySeconds = c.checkpointEvery;
    lo.timeLimitSeconds = c.timeLimit;
    lo.start = c.started;  // the limit counts from kiln's start: the queue slot's time
    lo.resume = c.resume;
    if (c.checkpoints()) lo.fingerprint = checkpointFingerprint(job, scenePath, c.load);
    lo.metadata = [&](const RenderStats& stats, const Film& film) {
        return renderMetadata(job, c, scenePath, stats, film);
    };
    lo.report = [](const std::string& text) { logInfo("{}", text); };
    LongRenderResult r = [&] {
        try {
            return renderLongFilm(job, lo);
        } catch (const CheckpointError& e) {
            throw UsageError(e.what());
        }
    }();
    auto t2 = std::chrono::steady_clock::now();
    std::string heatPath;
    int failures =
        writeOutputs(c, out, r.film,
                     r.totals.metadata.empty() ? renderMetadata(job, c, scenePath, r.stats, r.film)
                                               : r.totals.metadata,
                     heatPath);
    double writeTime = seconds(t2);
    failures += writeCheckpointAfterImages(c, lo, r, out, failures);
    printSummary(scenePath, out, heatPath, r.stats, loadTime, buildTime, writeTime);
    if (job.guided())
        logInfo("path guiding {}; trained in {:.3f}s (counted in the render time)",
                job.guidingText(), job.guideTrainingSeconds());
    if (c.json)
        printJsonResult(c, job.scene(), out, heatPath, r.stats, r.film,
                        {loadTime, buildTime, writeTime});
    if (failures) return 1;
    if (r.stats.interrupted || r.stats.timeLimitReached) {
        logInfo("{}: wrote {}the image so far (per-pixel sample counts in the EXR)",
                r.stats.interrupted ? "interrupted" : "time limit reached",
                lo.checkpointPath.empty() ? "" : out.checkpoint + " and ");
        return r.stats.interrupted ? kExitInterrupted : kExitTimeLimit;
    }
    if (c.traversalFloor) printTraversalFloor(*accel, job, r.stats);
    return 0;
}

void addRenderOptions(ArgParser& parser, RenderCommand& c) {
    addOutputOptions(parser, c);
    c.job.addOptions(parser);
    c.accel.addOptions(parser, true);
    addLoadOptions(parser, c.load);
    addEmitterOption(parser, c.load, c.job.job.path);
    addCameraOptions(parser, c);
    c.camera.addOptions(parser);
    addDebugOptions(parser, c);
    addLongRenderOptions(parser, c);
    addCompressionOption(parser, c);
    addCompositingOptions(parser, c);
    addQueueOptions(parser, c);
}

// The one scene file among the positional arguments; anything more is not an option.
void checkOneScene(const std::vector<std::string>& pos) {
    if (pos.empty()) throw UsageError("needs exactly one scene file (see 'kiln render --help')");
    if (pos.size() > 1)
        throw UsageError("needs exactly one scene file; '" + pos[1] +
                         "' is not an option (see 'kiln render --help')");
}

// The checks of the options alone, before anything is opened: the job's options, the long-render
// combinations, the camera override and the debug pair.
RenderJobOptions checkedJobOptions(const RenderCommand& c) {
    RenderJobOptions jobOptions = c.job.finish();
    applyLongRenderOptions(c, jobOptions);
    c.camera.check();
    if ((c.debugX >= 0) != (c.debugSample >= 0))
        throw UsageError("--pixel and --sample go together");
    return jobOptions;
}

}  // namespace

void checkRenderArguments(const std::vector<std::string>& args) {
    RenderCommand c;
    ArgParser parser("render", "SCENE [options]");
    addRenderOptions(parser, c);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) throw UsageError("--help is not a render option");
    checkOneScene(pos);
    checkedJobOptions(c);
    try {
        checkColorConfig(c.display, c.view);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

int runRender(const std::vector<std::string>& args) {
    // From the start a signal stops the work and saves what it has (a farm may send SIGTERM or
    // SIGUSR1 while the scene loads).
    SignalScope signals;
    RenderCommand c;
    ArgParser parser("render", "SCENE [options]   (writes OUT.exr and OUT.png)");
    addRenderOptions(parser, c);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        std::fputs(kExitCodes, stdout);
        return 0;
    }
    checkOneScene(pos);
    const std::string& scenePath = pos[0];
    RenderJobOptions jobOptions = checkedJobOptions(c);
    applyCompositingOptions(c, jobOptions);
    applyQueueOptions(c, jobOptions);
    checkColour(c);
    OutputPaths out = outputPaths(c, scenePath);
    checkOutputWritable(out);
    checkOutputsFit(c, jobOptions, out);

    auto t0 = std::chrono::steady_clock::now();
    Scene scene = loadScene(scenePath, c.load);
    double loadTime = seconds(t0);
    c.camera.apply(scene);
    applyThinLens(scene, c);
    for (const std::string& w : scene.warnings) logWarning("{}: {}", scenePath, w);
    auto t1 = std::chrono::steady_clock::now();
    std::unique_ptr<Accelerator> accel = c.accel.build(scene, &jobOptions);
    double buildTime = seconds(t1);
    RenderJob job(scene, *accel, jobOptions);
    warnHemisphereBlind(job, scenePath);
    if (c.debugX >= 0 || c.debugSample >= 0) return printDebugSample(job, c);
    // What the camera will see decides the black-image warning (a few thousand samples).
    if (std::optional<std::string> black = blackImageWarning(probeFrame(job), c.exposure)) {
        logWarning("{}: {}", scenePath, *black);
        c.warnings.push_back(*black);
    }

    addSceneToExr(c.exr, scene, jobOptions.settings, jobOptions.aovs);
    c.exr.software = fmt::format("kiln {} (commit {})", KILN_VERSION, gitCommit());
    return renderLong(c, job, accel, scenePath, out, loadTime, buildTime);
}

}  // namespace kiln
