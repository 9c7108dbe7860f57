// kiln bench accuracy: what accuracy costs in time on one scene.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "color/image_output.h"
#include "integrators/path.h"
#include "integrators/render_plan.h"
#include "renderer/accuracy.h"
#include "renderer/cli_args.h"
#include "renderer/commands.h"
#include "renderer/render_loop.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

struct Setting {
    PathOptions path;
    int spp = 1;
    int adaptiveBatch = 0;
    float adaptiveTolerance = 0;
    bool referenceAccel = false;
};

// One render with its time, rays and image.
struct Rendered {
    Image image;
    double seconds = 0, meanSpp = 0;
    uint64_t rays = 0;
};

Rendered render(const Scene& scene, const Accelerator& accel, const Setting& s, int w, int h,
                uint64_t seed, const AovRequest& aovs) {
    PathIntegrator integrator(scene, accel, s.path);
    integrator.setAovs(aovs);
    RenderSettings settings;
    settings.width = w, settings.height = h, settings.spp = s.spp, settings.seed = seed,
    settings.progress = false;
    settings.adaptiveBatch = s.adaptiveBatch, settings.adaptiveTolerance = s.adaptiveTolerance;
    Film film(w, h, aovs);
    RenderStats stats = renderImage(scene, integrator, settings, film);
    return {Image::fromFilm(film), stats.seconds, double(stats.samples) / (double(w) * h),
            stats.rays};
}

uint64_t fnv(const std::string& s, uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

// The reference for a depth, from the cache when its key matches, else rendered and cached as EXR.
Image reference(const Scene& scene, const Accelerator& accel, const AccuracyOptions& o, int depth,
                double& seconds, bool& cached) {
    std::error_code ec;
    std::string key = o.scene + "|" + std::to_string(fs::file_size(o.scene, ec)) + "|" +
                      std::to_string(fs::last_write_time(o.scene, ec).time_since_epoch().count()) +
                      "|" + std::to_string(o.width) + "x" + std::to_string(o.height) + "|" +
                      std::to_string(o.referenceSpp) + "|m" + std::to_string(depth) + "|" +
                      KILN_VERSION + "|aovs:" + o.aovs;
    char name[64];
    std::snprintf(name, sizeof name, "reference-m%d-%016llx.exr", depth,
                  (unsigned long long)fnv(key));
    std::string path = (fs::path(o.outDir) / name).string();
    if (auto in = OIIO::ImageInput::open(path)) {
        const OIIO::ImageSpec& spec = in->spec();
        int v = spec.channelindex("variance");
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        if (v >= 0 && spec.width == o.width && spec.height == o.height &&
            in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) {
            Image img;
            img.width = spec.width, img.height = spec.height;
            size_t count = size_t(spec.width) * spec.height;
            for (size_t i = 0; i < count; ++i) {
                const float* p = &px[i * spec.nchannels];
                img.pixels.emplace_back(p[0], p[1], p[2]);
                img.variance.push_back(p[v]);
            }
            AovLayout layout(AovRequest::parse(o.aovs, depth));  // kept alive for the loop
            for (const AovChannel& c : layout.channels()) {
                if (c.name.size() < 3 || c.name.compare(c.name.size() - 2, 2, ".R") != 0) continue;
                std::string layer = c.name.substr(0, c.name.size() - 2);
                int r = spec.channelindex(layer + ".R"), g = spec.channelindex(layer + ".G"),
                    b = spec.channelindex(layer + ".B");
                if (r < 0 || g < 0 || b < 0) continue;
                img.layerNames.push_back(layer);
                img.layers.emplace_back();
                for (size_t i = 0; i < count; ++i) {
                    const float* p = &px[i * spec.nchannels];
                    img.layers.back().emplace_back(p[r], p[g], p[b]);
                }
            }
            cached = true;
            return img;
        }
    }
    Setting s;
    s.path.maxDepth = depth;
    s.spp = o.referenceSpp;
    PathIntegrator integrator(scene, accel, s.path);
    RenderSettings settings;
    settings.width = o.width, settings.height = o.height, settings.spp = s.spp, settings.seed = 999;
    settings.progress = false;
    AovRequest aovs = AovRequest::parse("variance," + o.aovs, depth);
    integrator.setAovs(aovs);
    Film film(o.width, o.height, aovs);
    RenderStats stats = renderImage(scene, integrator, settings, film);
    seconds += stats.seconds;
    writeExr(path, film,
             {{"scene", o.scene},
              {"spp", std::to_string(s.spp)},
              {"max_depth", std::to_string(depth)},
              {"cache_key", key}});
    return Image::fromFilm(film);
}

std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

// Time at which the uniform series reaches a given relMSE: log-log interpolation between the
// bracketing points, or extrapolation along the last two points' slope below the smallest measured
// error
// (`extrapolated` set). 0 when it cannot be told.
double timeAtError(const std::vector<AccuracyRun>& uniform, double relMse, bool& extrapolated) {
    extrapolated = false;
    auto along = [&](const AccuracyRun& a, const AccuracyRun& b) {
        if (a.error.relMse <= 0 || b.error.relMse <= 0 || a.error.relMse == b.error.relMse)
            return 0.0;
        double f = std::log(relMse / a.error.relMse) / std::log(b.error.relMse / a.error.relMse);
        return std::exp(std::log(a.seconds) + f * (std::log(b.seconds) - std::log(a.seconds)));
    };
    for (size_t i = 1; i < uniform.size(); ++i)
        if (uniform[i - 1].error.relMse >= relMse && uniform[i].error.relMse <= relMse)
            return along(uniform[i - 1], uniform[i]);
    if (uniform.size() >= 2 && relMse < uniform.back().error.relMse) {
        extrapolated = true;
        return along(uniform[uniform.size() - 2], uniform.back());
    }
    return 0;
}

void writeOutputs(const AccuracyOptions& o, const AccuracyResult& r) {
    std::ofstream csv(fs::path(o.outDir) / "accuracy.csv");
    csv << "group,label,spp,mean_spp,light_samples,sampling,max_depth,roulette,adaptive_tolerance,"
           "accel,seconds,rays,"
           "rmse,rel_mse,bias,efficiency";
    std::vector<std::string> layers;
    if (!r.runs.empty())
        for (const auto& [name, e] : r.runs.front().aovErrors)
            layers.push_back(name), csv << ",rel_mse_" << name;
    csv << "\n";
    for (const AccuracyRun& a : r.runs) {
        csv << a.group << "," << a.label << "," << a.spp << "," << a.meanSpp << ","
            << a.lightSamples << "," << a.sampling << "," << a.maxDepth << "," << a.roulette << ","
            << a.adaptiveTolerance << "," << a.accel << "," << a.seconds << "," << a.rays << ","
            << a.error.rmse << "," << a.error.relMse << "," << a.error.bias << "," << a.efficiency;
        for (size_t k = 0; k < layers.size(); ++k)
            csv << "," << (k < a.aovErrors.size() ? a.aovErrors[k].second.relMse : 0.0);
        csv << "\n";
    }

    std::map<std::string, PlotSeries> byTime, bySpp;
    std::vector<AccuracyRun> uniform;
    for (const AccuracyRun& a : r.runs) {
        std::string series = a.group == "spp"        ? "path (GI)"
                             : a.group == "strategy" ? "direct: " + a.sampling
                                                     : "";
        if (a.group == "adaptive") series = "adaptive (GI)";
        if (series.empty()) continue;
        byTime[series].name = series;
        byTime[series].x.push_back(a.seconds);
        byTime[series].y.push_back(a.error.relMse);
        if (a.group != "adaptive") {
            bySpp[series].name = series;
            bySpp[series].x.push_back(a.spp);
            bySpp[series].y.push_back(a.error.relMse);
        }
        if (a.group == "spp") uniform.push_back(a);
    }
    auto values = [](const std::map<std::string, PlotSeries>& m) {
        std::vector<PlotSeries> v;
        for (const auto& [k, s] : m) v.push_back(s);
        return v;
    };
    std::string title = fs::path(o.scene).filename().string();
    std::ofstream(fs::path(o.outDir) / "error_vs_time.svg") << svgLogLogPlot(
        title + ": error against time", "render time (s)", "relative MSE", values(byTime), true);
    std::ofstream(fs::path(o.outDir) / "spp.svg")
        << svgLogLogPlot(title + ": error against samples per pixel", "samples per pixel",
                         "relative MSE", values(bySpp), true);

    // Plain-words summary.
    std::ofstream md(fs::path(o.outDir) / "summary.md");
    md << "### " << title << "\n\n";
    md << o.width << "x" << o.height << ", references at " << o.referenceSpp << " spp ("
       << (r.referenceCached ? "cached" : fmt(r.referenceSeconds) + " s")
       << "); errors are luminance relMSE "
       << "(x - r)^2 / (r^2 + 0.01) with the reference's own variance removed.\n\n";
    std::vector<double> spp, rel, secs, rmse;
    for (const AccuracyRun& a : uniform)
        spp.push_back(a.spp), rel.push_back(a.error.relMse), secs.push_back(a.seconds),
            rmse.push_back(a.error.rmse);
    double slopeSpp = logLogSlope(spp, rel), slopeTime = logLogSlope(secs, rmse);
    md << "- **Variance falls as 1/spp**: relMSE against spp has log-log slope **" << fmt(slopeSpp)
       << "** (expected -1; " << (std::abs(slopeSpp + 1) <= 0.15 ? "within" : "OUTSIDE")
       << " the +-0.15 tolerance) over " << spp.size() << " spp counts ("
       << (spp.empty() ? 0 : spp.front()) << " to " << (spp.empty() ? 0 : spp.back()) << ").";
    if (std::abs(slopeSpp + 1) > 0.15 && r.caustics)
        md << " The render plan finds caustics here: light through glass or mirrors onto diffuse "
              "surfaces, found only "
              "by rare BSDF-sampled paths. Their contribution is heavy-tailed: low sample counts "
              "usually miss it, so their "
              "measured error looks small, and the reference itself still carries caustic noise "
              "that its variance "
              "estimate underrates, a floor under the high counts. Both flatten the measured "
              "slope; it is the "
              "caustics, not the estimator, that converge slowly here.";
    md << "\n";
    if (slopeTime < 0)
        md << "- **To halve the error** (RMSE) of the path tracer on this scene, spend **"
           << fmt(std::pow(2.0, -1.0 / slopeTime)) << "x the time** (measured RMSE-time slope "
           << fmt(slopeTime) << ").\n";
    // MIS against hemisphere sampling at equal spp (direct lighting).
    std::map<int, double> hemi, mis, light;
    for (const AccuracyRun& a : r.runs)
        if (a.group == "strategy")
            (a.sampling == "hemisphere" ? hemi
             : a.sampling == "mis"      ? mis
                                        : light)[a.spp] = a.efficiency;
    std::vector<double> ratios;
    for (const auto& [n, e] : mis)
        if (hemi.count(n) && hemi[n] > 0) ratios.push_back(e / hemi[n]);
    if (!ratios.empty()) {
        std::sort(ratios.begin(), ratios.end());
        md << "- **MIS against uniform hemisphere sampling** (direct lighting, equal spp): MIS is "
              "**"
           << fmt(ratios[ratios.size() / 2]) << "x more efficient** (median of " << ratios.size()
           << " spp counts; efficiency = 1 / (relMSE x time)).\n";
    }
    auto has = [&](const char* g) {
        return std::any_of(r.runs.begin(), r.runs.end(),
                           [&](const AccuracyRun& a) { return a.group == g; });
    };
    if (has("depth"))
        md << "- **Depth truncation** (64 spp against the full-depth reference; bias is the error "
              "more samples cannot "
              "remove):\n\n  | setting | bias (mean luminance) | bias / image mean | relMSE | time "
              "(s) |\n  |---|---:|---:|---:|---:|\n";
    for (const AccuracyRun& a : r.runs)
        if (a.group == "depth")
            md << "  | " << a.label << " | " << fmt(a.error.bias) << " | "
               << (a.error.referenceMean > 0
                       ? fmt(100 * a.error.bias / a.error.referenceMean) + " %"
                       : "-")
               << " | " << fmt(a.error.relMse) << " | " << fmt(a.seconds) << " |\n";
    if (has("adaptive"))
        md << "\n- **Adaptive sampling** (CS184 rule, batch 32, up to " << o.maxSpp
           << " spp) against uniform spp at equal error:\n\n"
           << "  | tolerance | mean spp | relMSE | time (s) | uniform time at that error | saved "
              "|\n  |---|---:|---:|---:|---:|---:|\n";
    for (const AccuracyRun& a : r.runs)
        if (a.group == "adaptive") {
            bool extrapolated;
            double t = timeAtError(uniform, a.error.relMse, extrapolated);
            md << "  | " << a.adaptiveTolerance << " | " << fmt(a.meanSpp) << " | "
               << fmt(a.error.relMse) << " | " << fmt(a.seconds) << " | "
               << (t > 0 ? fmt(t) + (extrapolated ? " (extrapolated)" : "") : "out of range")
               << " | " << (t > 0 ? fmt(t / a.seconds) + "x" : "-") << " |\n";
        }
    if (has("light_samples")) md << "\n- **Light samples** (direct lighting, 16 spp): ";
    for (const AccuracyRun& a : r.runs)
        if (a.group == "light_samples")
            md << "-l " << a.lightSamples << ": relMSE " << fmt(a.error.relMse) << " in "
               << fmt(a.seconds) << " s; ";
    if (!uniform.empty() && !uniform.back().aovErrors.empty()) {
        md << "\n- **AOV errors** (relMSE of each requested layer, spp sweep: ";
        for (const AccuracyRun& a : {uniform.front(), uniform.back()}) {
            md << a.spp << " spp:";
            for (const auto& [name, e] : a.aovErrors) md << " " << name << " " << fmt(e.relMse);
            md << (&a == &uniform.front() ? "; " : "");
        }
        md << ")";
    }
    if (has("accel")) md << "\n- **Accelerators** (16 spp): ";
    for (const AccuracyRun& a : r.runs)
        if (a.group == "accel")
            md << a.accel << " " << fmt(a.seconds) << " s (relMSE " << fmt(a.error.relMse) << "); ";
    std::vector<AccuracyRun> ranked = r.runs;
    std::sort(ranked.begin(), ranked.end(), [](const AccuracyRun& a, const AccuracyRun& b) {
        return a.efficiency > b.efficiency;
    });
    md << "\n\n- Most efficient settings (unbiased ones only: depth-truncated settings converge to "
          "something else):\n\n"
          "  | rank | setting | relMSE | time (s) | efficiency |\n  |---:|---|---:|---:|---:|\n";
    int rank = 0;
    for (const AccuracyRun& a : ranked) {
        if (a.group == "depth" || a.group == "strategy" || a.group == "light_samples" || rank >= 5)
            continue;
        md << "  | " << ++rank << " | " << a.group << " " << a.label << " | " << fmt(a.error.relMse)
           << " | " << fmt(a.seconds) << " | " << fmt(a.efficiency) << " |\n";
    }
    for (const std::string& s : r.skipped) md << "\n- skipped (over the time budget): " << s;
    md << "\n\nPlots: `error_vs_time.svg`, `spp.svg`; every run: `accuracy.csv`.\n";
}

}  // namespace

AccuracyResult runAccuracy(const AccuracyOptions& o) {
    AccuracyResult result;
    fs::create_directories(o.outDir);
    Scene scene = loadScene(o.scene);
    auto embree = makeEmbreeAccelerator(scene);
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    bool cachedGi = false, cachedDirect = false;
    Image giRef = reference(scene, *embree, o, 100, result.referenceSeconds, cachedGi);
    Image directRef = reference(scene, *embree, o, 1, result.referenceSeconds, cachedDirect);
    result.referenceCached = cachedGi && cachedDirect;
    result.caustics = planFor(scene, *embree, AovRequest{}).caustics;
    double budgetStart = elapsed();
    AovRequest aovs = AovRequest::parse(o.aovs, 100);

    auto run = [&](const std::string& group, const std::string& label, const Setting& s,
                   const Image& ref) {
        // Skip a setting whose predicted time (from its spp and the time per spp so far) would
        // break the budget.
        double perSpp = 0;
        for (const AccuracyRun& a : result.runs)
            perSpp = std::max(perSpp, a.seconds / std::max(1.0, a.meanSpp));
        double predicted = perSpp * s.spp;
        if (elapsed() - budgetStart + predicted > o.budgetSeconds) {
            result.skipped.push_back(group + " " + label);
            return;
        }
        std::unique_ptr<Accelerator> refAccel;
        if (s.referenceAccel) refAccel = makeReferenceAccelerator(scene);
        Rendered r =
            render(scene, s.referenceAccel ? *refAccel : *embree, s, o.width, o.height, 7, aovs);
        AccuracyRun a;
        a.group = group, a.label = label, a.spp = s.spp, a.lightSamples = s.path.lightSamples,
        a.maxDepth = s.path.maxDepth;
        a.sampling = s.path.sampling == DirectSampling::Mis     ? "mis"
                     : s.path.sampling == DirectSampling::Light ? "light"
                                                                : "hemisphere";
        a.roulette = s.path.roulette == Roulette::Off     ? "off"
                     : s.path.roulette == Roulette::Fixed ? "fixed"
                                                          : "throughput";
        a.accel = s.referenceAccel ? "reference" : "embree";
        a.adaptiveTolerance = s.adaptiveTolerance;
        a.seconds = r.seconds, a.meanSpp = r.meanSpp, a.rays = r.rays;
        a.error = compareImages(r.image, ref);
        for (const std::string& layer : ref.layerNames)
            a.aovErrors.emplace_back(layer, compareLayer(r.image, ref, layer));
        a.efficiency = efficiency(a.error.relMse, a.seconds);
        result.runs.push_back(a);
        std::fprintf(stderr, "  %-14s %-16s %8.3f s  relMSE %.4g\n", group.c_str(), label.c_str(),
                     a.seconds, a.error.relMse);
    };

    int maxSpp = o.quick ? std::min(o.maxSpp, 16) : o.maxSpp;
    for (int spp = 1; spp <= maxSpp; spp *= 2) {
        Setting s;
        s.spp = spp;
        run("spp", std::to_string(spp) + " spp", s, giRef);
    }
    for (DirectSampling d :
         {DirectSampling::Hemisphere, DirectSampling::Light, DirectSampling::Mis})
        for (int spp = 1; spp <= maxSpp; spp *= (o.quick ? 4 : 2)) {
            Setting s;
            s.spp = spp;
            s.path.maxDepth = 1;
            s.path.sampling = d;
            const char* n = d == DirectSampling::Mis     ? "mis"
                            : d == DirectSampling::Light ? "light"
                                                         : "hemisphere";
            run("strategy", std::string(n) + " " + std::to_string(spp), s, directRef);
        }
    if (o.quick) {
        writeOutputs(o, result);
        return result;
    }
    for (int l : {1, 4, 16, 64}) {
        Setting s;
        s.spp = 16;
        s.path.maxDepth = 1;
        s.path.lightSamples = l;
        run("light_samples", "-l " + std::to_string(l), s, directRef);
    }
    for (int m : {1, 2, 3, 5, 100})
        for (bool rr : {true, false}) {
            Setting s;
            s.spp = 64;
            s.path.maxDepth = m;
            s.path.roulette = rr ? Roulette::Throughput : Roulette::Off;
            run("depth", "m=" + std::to_string(m) + (rr ? " rr" : " no-rr"), s, giRef);
        }
    for (float tol : {0.2f, 0.1f, 0.05f, 0.02f, 0.01f}) {
        Setting s;
        s.spp = o.maxSpp;
        s.adaptiveBatch = 32;
        s.adaptiveTolerance = tol;
        run("adaptive", "tol=" + fmt(tol), s, giRef);
    }
    for (bool ref : {false, true}) {
        Setting s;
        s.spp = 16;
        s.referenceAccel = ref;
        run("accel", ref ? "reference" : "embree", s, giRef);
    }
    writeOutputs(o, result);
    return result;
}

int runAccuracyCommand(const std::vector<std::string>& args) {
    ArgParser parser("bench accuracy",
                     "SCENE [--budget SECONDS] [--out DIR] [-r W H] [--max-spp N] [--ref-spp N]");
    AccuracyOptions o;
    int budget = 300;
    parser.option("out", "o", 1, "DIR", "output folder (default accuracy/)",
                  [&](const std::vector<std::string>& v) { o.outDir = v[0]; });
    parser.intOption("budget", "", "seconds for the sweep, references excluded (default 300)",
                     budget, 1, 1 << 24);
    parser.intOption("max-spp", "", "largest spp of the sweeps (default 1024)", o.maxSpp, 1,
                     1 << 16);
    parser.intOption("ref-spp", "", "reference spp (default 4096)", o.referenceSpp, 1, 1 << 24);
    parser.option("resolution", "r", 2, "W H", "image size (default 128 96)",
                  [&](const std::vector<std::string>& v) {
                      o.width = ArgParser::toInt("-r", v[0], 1, 8192);
                      o.height = ArgParser::toInt("-r", v[1], 1, 8192);
                  });
    parser.flag("quick", "", "a handful of settings (smoke test)", o.quick);
    parser.option("aov", "", 1, "LIST",
                  "also measure the error of these colour AOV layers (e.g. direct,indirect)",
                  [&](const std::vector<std::string>& v) { o.aovs = v[0]; });
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1) throw UsageError("needs exactly one scene file");
    o.scene = pos[0];
    o.budgetSeconds = budget;
    try {
        AovRequest::parse(o.aovs, 1);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--aov: ") + e.what());
    }
    AccuracyResult r = runAccuracy(o);
    std::ifstream summary(fs::path(o.outDir) / "summary.md");
    std::fputs(std::string(std::istreambuf_iterator<char>(summary), {}).c_str(), stdout);
    return r.runs.empty() ? 1 : 0;
}

}  // namespace kiln
