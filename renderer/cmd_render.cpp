#include <sys/resource.h>

#include <csignal>
#include <cstdio>
#include <filesystem>

#include "color/image_output.h"
#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/render_plan.h"
#include "renderer/accel_options.h"
#include "renderer/camera.h"
#include "renderer/commands.h"
#include "renderer/recording_accelerator.h"
#include "renderer/render_loop.h"
#include "scene/importers.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

extern "C" void onInterrupt(int) { renderCancelFlag().store(true); }

struct RenderOptions {
    RenderSettings settings;
    AcceleratorChoice accel;
    LoadOptions load;
    std::string integrator = "path";
    PathOptions path;
    std::string output;  // base path, or the -f file
    std::string display = "sRGB", view = "Standard";
    std::string aovList = "default";
    ExrOptions exr;
    bool heatMap = false;
    double crop[4] = {0, 1, 0, 1};  // --crop X0 X1 Y0 Y1
};

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The render again, every traversal call recorded, then the recorded calls traced alone: the
// part of the render time no shading speed-up can remove.
void printTraversalFloor(const Scene& scene, const Accelerator& accel, const RenderOptions& o,
                         const AovRequest& aovs, const RenderPlan& plan, const RenderStats& first) {
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
    std::unique_ptr<Integrator> integrator = makeIntegrator(o.integrator, scene, recorder, o.path);
    integrator->setAovs(aovs);
    if (auto* path = dynamic_cast<PathIntegrator*>(integrator.get())) path->usePlan(plan);
    RenderSettings settings = o.settings;
    settings.progress = false;
    Film film(settings.filmWidth(), settings.filmHeight(), aovs);
    film.setRegion(settings.filmOriginX(), settings.filmOriginY(), settings.width, settings.height);
    RenderStats again = renderImage(scene, *integrator, settings, film);
    ReplayStats replay = recorder.replay(settings.threads);
    if (replay.rays != again.rays || replay.hits != recorder.recordedHits())
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

}  // namespace

int runRender(const std::vector<std::string>& args) {
    RenderOptions o;
    ArgParser parser("render", "SCENE [options]   (writes OUT.exr and OUT.png)");
    parser.option("output", "o", 1, "OUT",
                  "output base name: OUT.exr and OUT.png (default: scene name)",
                  [&](const std::vector<std::string>& v) { o.output = v[0]; });
    parser.option("file", "f", 1, "OUT.png", "CS184 form: preview file; the EXR goes beside it",
                  [&](const std::vector<std::string>& v) { o.output = v[0]; });
    parser.option("resolution", "r", 2, "W H", "image size (default 800 600)",
                  [&](const std::vector<std::string>& v) {
                      o.settings.width = ArgParser::toInt("-r", v[0], 1, 32768);
                      o.settings.height = ArgParser::toInt("-r", v[1], 1, 32768);
                  });
    parser.option(
        "crop", "", 4, "X0 X1 Y0 Y1",
        "render only this window of the image, as fractions of its width and height (pbrt's "
        "crop window); the EXR keeps the full image as its display window",
        [&](const std::vector<std::string>& v) {
            for (int i = 0; i < 4; ++i) o.crop[i] = ArgParser::toDouble("--crop", v[size_t(i)]);
            if (!(o.crop[0] >= 0 && o.crop[0] < o.crop[1] && o.crop[1] <= 1 && o.crop[2] >= 0 &&
                  o.crop[2] < o.crop[3] && o.crop[3] <= 1))
                throw UsageError(
                    "--crop takes X0 X1 Y0 Y1 with 0 <= X0 < X1 <= 1 and 0 <= Y0 < "
                    "Y1 <= 1");
        });
    parser.intOption("spp", "s", "camera samples per pixel (default 1)", o.settings.spp, 1,
                     1 << 20);
    parser.intOption("threads", "t", "worker threads (default: all cores)", o.settings.threads, 1,
                     4096);
    parser.intOption("tile", "", "tile size in pixels (default 32)", o.settings.tileSize, 1, 4096);
    parser.option("seed", "", 1, "N", "random seed (default 0)",
                  [&](const std::vector<std::string>& v) {
                      o.settings.seed = uint64_t(ArgParser::toInt("--seed", v[0], 0, 2147483647));
                  });
    parser.option("integrator", "i", 1, "NAME",
                  std::string("light transport: ") + integratorNames(),
                  [&](const std::vector<std::string>& v) { o.integrator = v[0]; });
    parser.intOption("max-depth", "m",
                     "CS184 depth: 0 emission only, 1 direct lighting, >= 2 global illumination "
                     "(default 5)",
                     o.path.maxDepth, 0, 100000);
    parser.intOption("light-samples", "l", "light samples per shading point (default 1)",
                     o.path.lightSamples, 1, 65536);
    parser.option("adaptive", "a", 2, "BATCH TOL",
                  "adaptive sampling: test every BATCH samples, stop at "
                  "1.96 sigma/sqrt(n) <= TOL mu (CS184; -s is the maximum)",
                  [&](const std::vector<std::string>& v) {
                      o.settings.adaptiveBatch = ArgParser::toInt("-a", v[0], 1, 1 << 20);
                      o.settings.adaptiveTolerance = float(ArgParser::toDouble("-a", v[1]));
                      if (!(o.settings.adaptiveTolerance > 0))
                          throw UsageError("-a tolerance must be > 0");
                  });
    parser.option(
        "hemisphere", "H", 0, "",
        "direct light by uniform hemisphere sampling (same as --sampling hemisphere)",
        [&](const std::vector<std::string>&) { o.path.sampling = DirectSampling::Hemisphere; });
    parser.option(
        "sampling", "", 1, "mis|light|hemisphere", "direct lighting strategy (default mis)",
        [&](const std::vector<std::string>& v) {
            if (v[0] == "mis")
                o.path.sampling = DirectSampling::Mis;
            else if (v[0] == "light")
                o.path.sampling = DirectSampling::Light;
            else if (v[0] == "hemisphere")
                o.path.sampling = DirectSampling::Hemisphere;
            else
                throw UsageError("--sampling takes mis, light or hemisphere, got '" + v[0] + "'");
        });
    parser.option(
        "heuristic", "", 1, "power|balance", "MIS heuristic (default power)",
        [&](const std::vector<std::string>& v) {
            if (v[0] != "power" && v[0] != "balance")
                throw UsageError("--heuristic takes power or balance, got '" + v[0] + "'");
            o.path.powerHeuristic = v[0] == "power";
        });
    parser.option(
        "rr", "", 1, "throughput|fixed|off",
        "Russian roulette (default throughput; fixed = CS184's "
        "constant continuation)",
        [&](const std::vector<std::string>& v) {
            if (v[0] == "throughput")
                o.path.roulette = Roulette::Throughput;
            else if (v[0] == "fixed")
                o.path.roulette = Roulette::Fixed;
            else if (v[0] == "off")
                o.path.roulette = Roulette::Off;
            else
                throw UsageError("--rr takes throughput, fixed or off, got '" + v[0] + "'");
        });
    parser.option("rr-continue", "", 1, "P",
                  "continuation probability of --rr fixed (default 0.65)",
                  [&](const std::vector<std::string>& v) {
                      o.path.fixedContinuation = float(ArgParser::toDouble("--rr-continue", v[0]));
                      if (!(o.path.fixedContinuation > 0 && o.path.fixedContinuation <= 1))
                          throw UsageError("--rr-continue must be in (0, 1]");
                  });
    parser.option("bounce-only", "", 0, "",
                  "keep only light that bounced exactly -m times (accumulate bounces off)",
                  [&](const std::vector<std::string>&) { o.path.accumulateBounces = false; });
    parser.option(
        "microfacet", "", 1, "beckmann|ggx", "microfacet distribution (default beckmann, as CS184)",
        [&](const std::vector<std::string>& v) {
            if (v[0] == "beckmann")
                o.path.microfacet = MicrofacetModel::Beckmann;
            else if (v[0] == "ggx")
                o.path.microfacet = MicrofacetModel::GGX;
            else
                throw UsageError("--microfacet takes beckmann or ggx, got '" + v[0] + "'");
        });
    o.accel.addOptions(parser, true);
    parser.option("camera", "", 1, "file|framed",
                  "the file's camera as written, or the CS184 course "
                  "framing (default: course framing for Z-up COLLADA)",
                  [&](const std::vector<std::string>& v) {
                      if (v[0] != "file" && v[0] != "framed")
                          throw UsageError("--camera takes 'file' or 'framed', got '" + v[0] + "'");
                      o.load.cameraRule = v[0] == "file" ? LoadOptions::CameraRule::File
                                                         : LoadOptions::CameraRule::Framed;
                  });
    parser.option("env", "", 1, "MAP.exr", "add a lat-long environment light",
                  [&](const std::vector<std::string>& v) { o.load.environmentMap = v[0]; });
    float aperture = -1, focus = -1;
    parser.option("aperture", "", 1, "R",
                  "thin-lens aperture radius in scene units (default 0: pinhole)",
                  [&](const std::vector<std::string>& v) {
                      aperture = float(ArgParser::toDouble("--aperture", v[0]));
                      if (aperture < 0) throw UsageError("--aperture must be >= 0");
                  });
    parser.option("focus", "", 1, "D",
                  "thin-lens focal distance (default: distance to the scene centre)",
                  [&](const std::vector<std::string>& v) {
                      focus = float(ArgParser::toDouble("--focus", v[0]));
                      if (!(focus > 0)) throw UsageError("--focus must be > 0");
                  });
    parser.option("display", "", 1, "NAME", "OCIO display for the preview (default sRGB)",
                  [&](const std::vector<std::string>& v) { o.display = v[0]; });
    parser.option("view", "", 1, "NAME", "OCIO view for the preview (default Standard)",
                  [&](const std::vector<std::string>& v) { o.view = v[0]; });
    parser.option("aov", "", 1, "LIST",
                  std::string("EXR layers beside the beauty, comma-separated: ") +
                      AovRequest::names() +
                      " (default: emission,direct,indirect,albedo,N,Z,samples,variance)",
                  [&](const std::vector<std::string>& v) { o.aovList = v[0]; });
    parser.flag("half", "", "write colour layers as half floats (data layers stay float)",
                o.exr.half);
    parser.option("compression", "", 1, "zip|piz", "EXR compression (default zip)",
                  [&](const std::vector<std::string>& v) {
                      if (v[0] != "zip" && v[0] != "piz")
                          throw UsageError("--compression takes zip or piz, got '" + v[0] + "'");
                      o.exr.compression = v[0];
                  });
    parser.flag("heatmap", "",
                "also write OUT.samples.png, the per-pixel sample counts as a heat map "
                "(always with -a)",
                o.heatMap);
    bool generalPlan = false;
    parser.option(
        "plan", "", 1, "auto|general",
        "auto (default): the path specialised for what the scene holds; "
        "general: every feature on (the baseline the specialisations are checked against)",
        [&](const std::vector<std::string>& v) {
            if (v[0] != "auto" && v[0] != "general")
                throw UsageError("--plan takes auto or general, got '" + v[0] + "'");
            generalPlan = v[0] == "general";
        });
    int debugX = -1, debugY = -1, debugSample = -1;
    parser.option("pixel", "", 2, "X Y",
                  "debug: trace only this pixel (with --sample) and print what it returns",
                  [&](const std::vector<std::string>& v) {
                      debugX = ArgParser::toInt("--pixel", v[0], 0, 1 << 20);
                      debugY = ArgParser::toInt("--pixel", v[1], 0, 1 << 20);
                  });
    parser.intOption("sample", "", "debug: the sample index to replay with --pixel", debugSample, 0,
                     1 << 30);
    bool quiet = false;
    parser.flag("quiet", "q", "no progress bar", quiet);
    bool traversalFloor = false;
    parser.flag("traversal-floor", "",
                "benchmark: after the render, render again recording every ray, trace the "
                "recorded rays alone in the same calls, and print how much of the render time "
                "traversal is (needs 32 bytes of memory per ray)",
                traversalFloor);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1)
        throw UsageError("needs exactly one scene file (see 'kiln render --help')");
    o.settings.progress = !quiet;
    if (o.crop[0] > 0 || o.crop[1] < 1 || o.crop[2] > 0 || o.crop[3] < 1) {
        // pbrt's rule: pixel bounds are the ceilings of the scaled fractions.
        auto at = [](double f, int n) { return int(std::ceil(f * double(n))); };
        o.settings.regionX0 = at(o.crop[0], o.settings.width);
        o.settings.regionX1 = at(o.crop[1], o.settings.width);
        o.settings.regionY0 = at(o.crop[2], o.settings.height);
        o.settings.regionY1 = at(o.crop[3], o.settings.height);
        if (o.settings.regionX1 <= o.settings.regionX0 ||
            o.settings.regionY1 <= o.settings.regionY0)
            throw UsageError("--crop window holds no pixel at " + std::to_string(o.settings.width) +
                             "x" + std::to_string(o.settings.height));
    }

    try {
        checkDisplayView(o.display, o.view);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    namespace fs = std::filesystem;
    std::string base = o.output.empty() ? fs::path(pos[0]).stem().string() : o.output;
    std::string ext = fs::path(base).extension().string();
    std::string previewPath = base + ".png", exrPath = base + ".exr";
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
        previewPath = base;
        exrPath = fs::path(base).replace_extension(".exr").string();
    } else if (ext == ".exr") {
        exrPath = base;
        previewPath = fs::path(base).replace_extension(".png").string();
    }
    fs::path dir = fs::path(exrPath).parent_path();
    if (!dir.empty() && !fs::is_directory(dir))
        throw UsageError("output directory '" + dir.string() + "' does not exist");

    auto t0 = std::chrono::steady_clock::now();
    Scene scene = loadScene(pos[0], o.load);
    double loadTime = seconds(t0);
    if (aperture > 0) {
        scene.camera.apertureRadius = aperture;
        scene.camera.focalDistance =
            focus > 0 ? focus
                      : std::max(1e-6f, dot(scene.worldBounds().centroid() - scene.camera.position,
                                            scene.camera.forward));
    }
    for (const std::string& w : scene.warnings)
        std::fprintf(stderr, "kiln: warning: %s: %s\n", pos[0].c_str(), w.c_str());

    auto t1 = std::chrono::steady_clock::now();
    std::unique_ptr<Accelerator> accel = o.accel.build(scene);
    double buildTime = seconds(t1);
    std::unique_ptr<Integrator> integrator;
    try {
        integrator = makeIntegrator(o.integrator, scene, *accel, o.path);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }

    AovRequest aovs;
    try {
        aovs = AovRequest::parse(o.aovList, o.path.maxDepth);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--aov: ") + e.what());
    }
    integrator->setAovs(aovs);
    RenderPlan plan = planFor(scene, *accel, aovs, generalPlan);
    if (auto* path = dynamic_cast<PathIntegrator*>(integrator.get())) path->usePlan(plan);
    if (plan.deltaLightsOnly && o.path.sampling == DirectSampling::Hemisphere &&
        o.integrator == "path")
        std::fprintf(
            stderr,
            "kiln: warning: %s: hemisphere sampling cannot see point, spot or directional lights, "
            "the only lights here: the image will be black but for emitters\n",
            pos[0].c_str());

    if (debugX >= 0 || debugSample >= 0) {
        if (debugX < 0 || debugSample < 0) throw UsageError("--pixel and --sample go together");
        if (debugX >= o.settings.width || debugY >= o.settings.height)
            throw UsageError("--pixel is outside the " + std::to_string(o.settings.width) + "x" +
                             std::to_string(o.settings.height) + " image");
        RayCounter counter;
        SampleRecord r =
            traceSample(scene, *integrator, o.settings, debugX, debugY, debugSample, counter);
        std::printf("pixel %d %d sample %d: L = %.9g %.9g %.9g (%s), %llu rays\n", debugX, debugY,
                    debugSample, r.L.x, r.L.y, r.L.z, isFinite(r.L) ? "finite" : "NOT FINITE",
                    (unsigned long long)counter.rays);
        std::printf("  emission %.9g direct %.9g indirect %.9g (luminance); depth %.9g\n",
                    luminance(r.emission), luminance(r.direct), luminance(r.indirect), r.depth);
        return isFinite(r.L) ? 0 : 1;
    }

    renderCancelFlag().store(false);
    auto previous = std::signal(SIGINT, onInterrupt);
    Film film(o.settings.filmWidth(), o.settings.filmHeight(), aovs);
    film.setRegion(o.settings.filmOriginX(), o.settings.filmOriginY(), o.settings.width,
                   o.settings.height);
    RenderStats stats = renderImage(scene, *integrator, o.settings, film);
    std::signal(SIGINT, previous);

    auto t2 = std::chrono::steady_clock::now();
    CameraModel camera(scene.camera, o.settings.width, o.settings.height);
    Metadata meta{
        {"scene", pos[0]},
        {"integrator", integrator->name()},
        {"accelerator", accel->stats().description},
        {"spp", std::to_string(o.settings.spp)},
        {"mean_spp",
         std::to_string(double(stats.samples) / (double(film.width()) * film.height()))},
        {"seed", std::to_string(o.settings.seed)},
        {"resolution", std::to_string(o.settings.width) + "x" + std::to_string(o.settings.height)},
        {"render_seconds", std::to_string(stats.seconds)},
        {"hfov", std::to_string(camera.hFovDeg())},
        {"vfov", std::to_string(camera.vFovDeg())},
        {"interrupted", stats.interrupted ? "yes" : "no"},
        {"max_depth", std::to_string(o.path.maxDepth)},
        {"light_samples", std::to_string(o.path.lightSamples)},
        {"sampling", o.path.sampling == DirectSampling::Mis     ? "mis"
                     : o.path.sampling == DirectSampling::Light ? "light"
                                                                : "hemisphere"},
        {"roulette", o.path.roulette == Roulette::Throughput ? "throughput"
                     : o.path.roulette == Roulette::Fixed    ? "fixed"
                                                             : "off"},
        {"accumulate_bounces", o.path.accumulateBounces ? "yes" : "no"},
        {"adaptive", o.settings.adaptiveBatch > 0 ? std::to_string(o.settings.adaptiveBatch) + " " +
                                                        std::to_string(o.settings.adaptiveTolerance)
                                                  : "off"},
        {"mis_heuristic", o.path.powerHeuristic ? "power" : "balance"},
        {"microfacet", o.path.microfacet == MicrofacetModel::GGX ? "ggx" : "beckmann"},
        {"camera", scene.framedByCourseRule ? "cs184-framing"
                   : scene.hasFileCamera    ? "file"
                                            : "default-framing"},
        {"aovs", o.aovList},
        {"threads", std::to_string(o.settings.threads)},
        {"rays", std::to_string(stats.rays)},
        {"display", o.display},
        {"view", o.view},
        {"working_space", "lin_rec709 (linear Rec.709 primaries, D65)"},
        {"plan", plan.compact()},
        {"plan_decisions", plan.text()},
        {"nonfinite_samples", std::to_string(stats.nonFiniteSamples)}};
    writeExr(exrPath, film, meta, o.exr);
    writePreview(previewPath, film, o.display, o.view);
    std::string heatPath;
    if (o.heatMap || o.settings.adaptiveBatch > 0) {
        heatPath = fs::path(exrPath).replace_extension(".samples.png").string();
        writeSampleHeatMap(heatPath, film);
    }
    double writeTime = seconds(t2);

    double mrays = stats.seconds > 0 ? double(stats.rays) / stats.seconds * 1e-6 : 0.0;
    std::fprintf(stderr,
                 "kiln: %s -> %s, %s%s%s\n"
                 "kiln: %llu samples, %llu rays, %.2f Mrays/s; time load %.3fs, build %.3fs, "
                 "render %.3fs, write %.3fs\n",
                 pos[0].c_str(), exrPath.c_str(), previewPath.c_str(), heatPath.empty() ? "" : ", ",
                 heatPath.c_str(), (unsigned long long)stats.samples,
                 (unsigned long long)stats.rays, mrays, loadTime, buildTime, stats.seconds,
                 writeTime);
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
                         pos[0].c_str(), b.x, b.y, b.sample);
    }
    if (stats.interrupted) {
        std::fprintf(
            stderr,
            "kiln: interrupted: wrote the image so far (per-pixel sample counts in the EXR)\n");
        return 130;
    }
    if (traversalFloor) printTraversalFloor(scene, *accel, o, aovs, plan, stats);
    return 0;
}

}  // namespace kiln
