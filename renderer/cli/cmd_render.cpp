// kiln render: option parsing, then one RenderJob, then the outputs.
#include <sys/resource.h>

#include <csignal>
#include <cstdio>
#include <filesystem>

#include "color/image_output.h"
#include "renderer/accel/recording_accelerator.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/camera_options.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/render_options.h"
#include "renderer/core/memory.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

extern "C" void onInterrupt(int) { renderCancelFlag().store(true); }

namespace fs = std::filesystem;

struct RenderCommand {
    RenderJobArgs job;
    AcceleratorChoice accel;
    LoadOptions load;
    CameraOptions camera;
    std::string output;  // base path, or the -f file
    std::string display = "sRGB", view = "Standard";
    ExrOptions exr;
    bool heatMap = false, quiet = false, traversalFloor = false;
    float aperture = -1, focus = -1;
    int debugX = -1, debugY = -1, debugSample = -1;
};

struct OutputPaths {
    std::string exr, preview;
};

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void addCameraOptions(ArgParser& parser, RenderCommand& c) {
    parser.option("aperture", "", 1, "R",
                  "thin-lens aperture radius in scene units (default 0: pinhole)",
                  [&c](const std::vector<std::string>& v) {
                      c.aperture = float(ArgParser::toDouble("--aperture", v[0]));
                      if (c.aperture < 0) throw UsageError("--aperture must be >= 0");
                  });
    parser.option("focus", "", 1, "D",
                  "thin-lens focal distance (default: distance to the scene centre)",
                  [&c](const std::vector<std::string>& v) {
                      c.focus = float(ArgParser::toDouble("--focus", v[0]));
                      if (!(c.focus > 0)) throw UsageError("--focus must be > 0");
                  });
}

void addOutputOptions(ArgParser& parser, RenderCommand& c) {
    parser.option("output", "o", 1, "OUT",
                  "output base name: OUT.exr and OUT.png (default: scene name)",
                  [&c](const std::vector<std::string>& v) { c.output = v[0]; });
    parser.option("file", "f", 1, "OUT.png", "CS184 form: preview file; the EXR goes beside it",
                  [&c](const std::vector<std::string>& v) { c.output = v[0]; });
    parser.option("display", "", 1, "NAME", "OCIO display for the preview (default sRGB)",
                  [&c](const std::vector<std::string>& v) { c.display = v[0]; });
    parser.option("view", "", 1, "NAME", "OCIO view for the preview (default Standard)",
                  [&c](const std::vector<std::string>& v) { c.view = v[0]; });
    parser.flag("half", "", "write colour layers as half floats (data layers stay float)",
                c.exr.half);
    parser.option("compression", "", 1, "zip|piz", "EXR compression (default zip)",
                  [&c](const std::vector<std::string>& v) {
                      if (v[0] != "zip" && v[0] != "piz")
                          throw UsageError("--compression takes zip or piz, got '" + v[0] + "'");
                      c.exr.compression = v[0];
                  });
    parser.flag("heatmap", "",
                "also write OUT.samples.png, the per-pixel sample counts as a heat map "
                "(always with -a)",
                c.heatMap);
}

void addDebugOptions(ArgParser& parser, RenderCommand& c) {
    parser.option("pixel", "", 2, "X Y",
                  "debug: trace only this pixel (with --sample) and print what it returns",
                  [&c](const std::vector<std::string>& v) {
                      c.debugX = ArgParser::toInt("--pixel", v[0], 0, 1 << 20);
                      c.debugY = ArgParser::toInt("--pixel", v[1], 0, 1 << 20);
                  });
    parser.intOption("sample", "", "debug: the sample index to replay with --pixel", c.debugSample,
                     0, 1 << 30);
    parser.flag("quiet", "q", "no progress bar", c.quiet);
    parser.flag("traversal-floor", "",
                "benchmark: after the render, render again recording every ray, trace the "
                "recorded rays alone in the same calls, and print how much of the render time "
                "traversal is (needs 32 bytes of memory per ray)",
                c.traversalFloor);
}

OutputPaths outputPaths(const RenderCommand& c, const std::string& scenePath) {
    std::string base = c.output.empty() ? fs::path(scenePath).stem().string() : c.output;
    std::string ext = fs::path(base).extension().string();
    OutputPaths out{base + ".exr", base + ".png"};
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg")
        out = {fs::path(base).replace_extension(".exr").string(), base};
    else if (ext == ".exr")
        out = {base, fs::path(base).replace_extension(".png").string()};
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
    if (need > available) {
        char text[200];
        std::snprintf(
            text, sizeof text,
            "--traversal-floor: recording the render's %llu rays needs %.1f MiB, %.1f MiB "
            "available (the image is written; fewer samples or a --crop fit)",
            (unsigned long long)first.rays, double(need) / (1 << 20),
            double(available) / (1 << 20));
        throw UsageError(text);
    }
    RecordingAccelerator recorder(accel);
    RenderJob again(job, recorder);
    Film film = again.makeFilm();
    renderCancelFlag().store(false);
    RenderStats second = again.render(film);
    ReplayStats replay = recorder.replay(job.options().settings.threads);
    if (replay.rays != second.rays || replay.hits != recorder.recordedHits())
        throw std::logic_error("traversal floor: the replay traced other rays than the render");
    std::fprintf(stderr,
                 "kiln: traversal floor: the render's %llu rays traced again alone, in the same "
                 "calls: %.3fs (%.2f Mrays/s) against the render's %.3fs: traversal %.0f %%, "
                 "shading, sampling and film %.0f %%\n",
                 (unsigned long long)replay.rays, replay.seconds,
                 double(replay.rays) / replay.seconds * 1e-6, first.seconds,
                 100.0 * replay.seconds / first.seconds,
                 100.0 * (1.0 - replay.seconds / first.seconds));
    // Batched calls are 16-wide packets in Embree's default mode, loops of single rays otherwise.
    const char* kinds[4] = {"closest hit, one ray per call", "closest hit, batched",
                            "occlusion, one ray per call", "occlusion, batched"};
    for (size_t k = 0; k < 4; ++k)
        if (replay.raysOf[k])
            std::fprintf(stderr, "kiln:   %-32s %11llu rays %7.1f ns per ray per thread\n",
                         kinds[k], (unsigned long long)replay.raysOf[k],
                         replay.threadSeconds[k] / double(replay.raysOf[k]) * 1e9);
}

void warnHemisphereBlind(const RenderJob& job, const std::string& scenePath) {
    const RenderJobOptions& o = job.options();
    if (job.plan().deltaLightsOnly && o.path.sampling == DirectSampling::Hemisphere &&
        o.integrator == IntegratorKind::Path)
        std::fprintf(
            stderr,
            "kiln: warning: %s: hemisphere sampling cannot see point, spot or directional lights, "
            "the only lights here: the image will be black but for emitters\n",
            scenePath.c_str());
}

RenderStats renderInterruptibly(const RenderJob& job, Film& film) {
    renderCancelFlag().store(false);
    auto previous = std::signal(SIGINT, onInterrupt);
    RenderStats stats = job.render(film);
    std::signal(SIGINT, previous);
    return stats;
}

void printSummary(const std::string& scenePath, const OutputPaths& out, const std::string& heat,
                  const RenderStats& stats, double load, double build, double write) {
    double mrays = stats.seconds > 0 ? double(stats.rays) / stats.seconds * 1e-6 : 0.0;
    std::fprintf(stderr,
                 "kiln: %s -> %s, %s%s%s\n"
                 "kiln: %llu samples, %llu rays, %.2f Mrays/s; time load %.3fs, build %.3fs, "
                 "render %.3fs, write %.3fs\n",
                 scenePath.c_str(), out.exr.c_str(), out.preview.c_str(), heat.empty() ? "" : ", ",
                 heat.c_str(), (unsigned long long)stats.samples, (unsigned long long)stats.rays,
                 mrays, load, build, stats.seconds, write);
    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    std::fprintf(stderr, "kiln: peak resident memory %.1f MiB\n", double(usage.ru_maxrss) / 1024.0);
    if (stats.nonFiniteSamples) {
        std::fprintf(
            stderr,
            "kiln: warning: %llu non-finite samples were dropped (not written into the image)\n",
            (unsigned long long)stats.nonFiniteSamples);
        for (const BadSample& b : stats.firstBadSamples)
            std::fprintf(stderr,
                         "kiln:   replay with: kiln render %s ... --pixel %d %d --sample %d\n",
                         scenePath.c_str(), b.x, b.y, b.sample);
    }
}

}  // namespace

int runRender(const std::vector<std::string>& args) {
    RenderCommand c;
    ArgParser parser("render", "SCENE [options]   (writes OUT.exr and OUT.png)");
    addOutputOptions(parser, c);
    c.job.addOptions(parser);
    c.accel.addOptions(parser, true);
    addLoadOptions(parser, c.load);
    addCameraOptions(parser, c);
    c.camera.addOptions(parser);
    addDebugOptions(parser, c);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1)
        throw UsageError("needs exactly one scene file (see 'kiln render --help')");
    const std::string& scenePath = pos[0];
    RenderJobOptions jobOptions = c.job.finish();
    jobOptions.settings.progress = !c.quiet;
    try {
        checkDisplayView(c.display, c.view);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    OutputPaths out = outputPaths(c, scenePath);

    auto t0 = std::chrono::steady_clock::now();
    Scene scene = loadScene(scenePath, c.load);
    double loadTime = seconds(t0);
    c.camera.apply(scene);
    applyThinLens(scene, c);
    for (const std::string& w : scene.warnings)
        std::fprintf(stderr, "kiln: warning: %s: %s\n", scenePath.c_str(), w.c_str());
    auto t1 = std::chrono::steady_clock::now();
    std::unique_ptr<Accelerator> accel = c.accel.build(scene);
    double buildTime = seconds(t1);
    RenderJob job(scene, *accel, jobOptions);
    warnHemisphereBlind(job, scenePath);
    if (c.debugX >= 0 || c.debugSample >= 0) return printDebugSample(job, c);

    Film film = job.makeFilm();
    RenderStats stats = renderInterruptibly(job, film);
    auto t2 = std::chrono::steady_clock::now();
    Metadata meta = job.metadata(stats, film);
    meta["scene"] = scenePath;
    meta["aovs"] = c.job.aovList;
    meta["display"] = c.display;
    meta["view"] = c.view;
    writeExr(out.exr, film, meta, c.exr);
    writePreview(out.preview, film, c.display, c.view);
    std::string heatPath;
    if (c.heatMap || jobOptions.settings.adaptiveBatch > 0) {
        heatPath = fs::path(out.exr).replace_extension(".samples.png").string();
        writeSampleHeatMap(heatPath, film);
    }
    printSummary(scenePath, out, heatPath, stats, loadTime, buildTime, seconds(t2));
    if (stats.interrupted) {
        std::fprintf(
            stderr,
            "kiln: interrupted: wrote the image so far (per-pixel sample counts in the EXR)\n");
        return 130;
    }
    if (c.traversalFloor) printTraversalFloor(*accel, job, stats);
    return 0;
}

}  // namespace kiln
