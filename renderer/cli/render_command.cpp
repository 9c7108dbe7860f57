#include "renderer/cli/render_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <optional>

#include "renderer/build_info.h"
#include "renderer/cli/output_check.h"
#include "renderer/core/log.h"
#include "renderer/core/memory.h"
#include "renderer/denoise_film.h"
#include "renderer/exr_scene.h"
#include "renderer/long_render.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

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
    parser.option("look", "", 1, "NAME", "OCIO look applied to the preview before the view",
                  [&c](const std::vector<std::string>& v) { c.look = v[0]; });
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
    parser.flag("no-final-checkpoint", "",
                "a finished render of the whole frame leaves no OUT.ckpt: none written at its end, "
                "one written during it removed (one stopped early, or a --sample-range or --crop "
                "shard, still writes it); kiln batch and farm frames without --keep-checkpoints",
                c.noFinalCheckpoint);
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

void addDenoiseOptions(ArgParser& parser, RenderCommand& c) {
    OptionGroup group(parser, "Output");
    parser.flag("denoise", "",
                "keep even/odd half-buffers and write the beauty denoised (NFOR; the raw one as "
                "noisy.R/G/B; docs/denoise.md)",
                c.denoise);
    parser.option(
        "denoise-aovs", "", 1, "LIST",
        std::string("with --denoise, denoise these rendered light-path AOVs too, each "
                    "with its own half-buffers (the raw layer as noisy.LAYER.R/G/B), "
                    "comma-separated: ") +
            AovRequest::lightNames(),
        [&c](const std::vector<std::string>& v) { c.denoisedLight = parseDenoisedAovs(v[0]); });
}

// --denoise-aovs needs --denoise and names layers the render writes.
void applyDenoiseOptions(const RenderCommand& c, RenderJobOptions& options) {
    if (c.denoise) options.aovs.add(AovKind::DenoiseHalves);
    if (!c.denoisedLight) return;
    if (!c.denoise) throw UsageError("--denoise-aovs needs --denoise");
    if (uint32_t missing = c.denoisedLight & ~options.aovs.mask)
        throw UsageError("--denoise-aovs: '" + AovRequest::namesOf(missing) +
                         "' not rendered (add it to --aov)");
    options.aovs.denoisedLight = c.denoisedLight;
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

void applyCompositingOptions(const RenderCommand& c, RenderJobOptions& options) {
    options.aovs.transparent = c.transparent;
    options.aovs.depth = c.depth;
}

void applyLongRenderOptions(const RenderCommand& c, RenderJobOptions& o) {
    RenderSettings& s = o.settings;
    if (c.rangeStart >= 0) s.sampleStart = c.rangeStart, s.spp = c.rangeEnd;
    if (s.sampleStart > 0 && s.adaptiveStep() > 0)
        throw UsageError(
            "--sample-range must start at 0 with -a or --noise-threshold: adaptive sampling "
            "decides from the samples before");
}

void applyThinLens(Scene& scene, const RenderCommand& c, const Bounds3& stored) {
    if (c.aperture <= 0) return;
    scene.camera.apertureRadius = c.aperture;
    scene.camera.focalDistance =
        c.focus > 0
            ? c.focus
            : std::max(1e-6f, dot(stored.centroid() - scene.camera.position, scene.camera.forward));
}

// Which kiln wrote the file: the libraries as kiln:libraries (the commit goes in Software).
void addBuildToMetadata(Metadata& meta) {
    meta["libraries"] = libraryVersions();
    meta["ocio_config"] = colorConfigPath();
}

}  // namespace

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
    addDenoiseOptions(parser, c);
    addQueueOptions(parser, c);
}

RenderJobOptions renderJobOptions(const RenderCommand& c) {
    RenderJobOptions options = c.job.finish();
    applyLongRenderOptions(c, options);
    applyCompositingOptions(c, options);
    applyDenoiseOptions(c, options);
    return options;
}

// The OCIO config, display and view checked before any work; the defaults filled in.
void checkFilmFits(const RenderJobOptions& o, bool checkpoints) {
    const OutputSizes need = estimateOutputs(o, checkpoints);
    uint64_t memory = need.film + need.writeMemory, available = availableMemoryBytes();
    if (memory > available)
        throw UsageError("the film and the EXR write need " + std::to_string(memory >> 20) +
                         " MiB, " + std::to_string(available >> 20) +
                         " MiB available (a smaller -r, --crop or fewer --aov fit)");
}

void checkColour(RenderCommand& c) {
    try {
        ColorSetup setup = checkColorConfig(c.display, c.view, c.look);
        c.display = setup.display, c.view = setup.view, c.colourConfig = setup.configPath;
        c.exr.colorSpace = setup.sceneLinear;
        for (const std::string& w : setup.warnings) logWarning("{}", w);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

void applyCameraOptions(Scene& scene, const RenderCommand& c, const Bounds3& stored) {
    c.camera.apply(scene, stored);
    applyThinLens(scene, c, stored);
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
    // -H probes are traced as closest hits, blind to media (docs/light-transport.md).
    if (job.plan().media && o.path.sampling == DirectSampling::Hemisphere &&
        o.integrator == IntegratorKind::Path)
        logWarning(
            "{}: hemisphere sampling does not see participating media: their light is "
            "wrong (use --sampling mis)",
            scenePath);
}

void warnIdleOptions(const RenderJob& job, const RenderCommand& c) {
    const RenderSettings& s = job.options().settings;
    if (const int step = s.adaptiveStep(); step > 0 && step >= s.spp)
        logWarning(
            "adaptive sampling tests a pixel first at {} samples and -s is {}: every pixel takes "
            "all {} (a smaller -a batch or --adaptive-min-spp, or a larger -s, lets it stop early)",
            step, s.spp, s.spp);
    if (c.denoise && s.spp < 2)
        logWarning(
            "--denoise needs 2 samples a pixel or more (its two half buffers); at -s {} "
            "the image is written as rendered",
            s.spp);
}

void addSceneToOutputs(RenderCommand& c, const Scene& scene, const RenderJobOptions& options) {
    addSceneToExr(c.exr, scene, options.settings, options.aovs);
    c.exr.software = fmt::format("kiln {} (commit {})", KILN_VERSION, gitCommit());
}

OutputPaths outputPaths(const RenderCommand& c, const std::string& scenePath) {
    OutputPaths out = outputNames(c, scenePath);
    checkOutputBase(c.output.empty() ? fs::path(scenePath).stem().string() : c.output);
    return out;
}

OutputPaths outputNames(const RenderCommand& c, const std::string& scenePath) {
    std::string base = c.output.empty() ? fs::path(scenePath).stem().string() : c.output;
    std::string ext = fs::path(base).extension().string();
    OutputPaths out{base + ".exr", base + ".png", ""};
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg")
        out = {fs::path(base).replace_extension(".exr").string(), base, ""};
    else if (ext == ".exr")
        out = {base, fs::path(base).replace_extension(".png").string(), ""};
    out.checkpoint = fs::path(out.exr).replace_extension(".ckpt").string();
    return out;
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

DenoisedFrame denoiseFrame(const Film& film, int threads) {
    DenoisedFrame frame;
    denoiseForOutputs(film, threads, frame.exr, frame.meta);
    return frame;
}

bool writesHeatMap(const RenderCommand& c) {
    return c.heatMap || c.job.job.settings.adaptiveStep() > 0;
}

int writeOutputs(const RenderCommand& c, const OutputPaths& out, const Film& film,
                 const Metadata& meta, std::string& heatPath,
                 const std::function<void(const std::string&)>& onError,
                 std::vector<OutputWrite>* writes, const DenoisedFrame* denoised) {
    int failures = 0;
    auto attempt = [&failures, &onError, writes](const char* kind, const std::string& path,
                                                 auto&& write) {
        std::string error;
        try {
            write();
        } catch (const std::exception& e) {
            error = e.what();
            if (onError)
                onError(error);
            else
                logError("{}", error);
            ++failures;
        }
        if (writes) writes->push_back({kind, path, error});
    };
    ExrOptions exr = c.exr;
    Metadata denoisedMeta = meta;
    if (c.denoise && film.hasHalves()) {
        try {  // a denoiser failure is an error, but the raw image is still written
            std::optional<DenoisedFrame> own;
            const DenoisedFrame& frame =
                denoised ? *denoised : own.emplace(denoiseFrame(film, c.job.job.settings.threads));
            exr.denoised = frame.exr.denoised, exr.denoisedLayers = frame.exr.denoisedLayers;
            for (const auto& [key, value] : frame.meta) denoisedMeta[key] = value;
        } catch (const std::exception& e) {
            logError("{}: denoising failed: {}", out.exr, e.what());
            ++failures;
        }
    }
    attempt("exr", out.exr, [&] { writeExr(out.exr, film, denoisedMeta, exr); });
    attempt("preview", out.preview, [&] {
        writePreview(out.preview, film, c.display, c.view, c.exposure, c.look, exr.denoised.get());
    });
    if (writesHeatMap(c)) {
        heatPath = fs::path(out.exr).replace_extension(".samples.png").string();
        attempt("heatmap", heatPath, [&] { writeSampleHeatMap(heatPath, film); });
    }
    return failures;
}

}  // namespace kiln
