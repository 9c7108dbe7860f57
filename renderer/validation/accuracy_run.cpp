// kiln bench accuracy's sweep: renders each setting, compares it with a converged reference
// (cached as EXR between runs) and collects error against time.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "color/image_input.h"
#include "renderer/denoise_film.h"
#include "renderer/render_job.h"
#include "renderer/validation/accuracy.h"
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
    SamplerKind sampler = RenderSettings{}.sampler;
    bool denoise = false;  // the image measured is the denoised one; its time counts
};

// One render with its time, rays and image.
struct Rendered {
    Image image;
    double seconds = 0, meanSpp = 0;
    uint64_t rays = 0;
    bool guided = false;
};

Rendered render(const Scene& scene, const Accelerator& accel, const Setting& s, int w, int h,
                uint64_t seed, const AovRequest& aovs) {
    RenderJobOptions options;
    options.path = s.path;
    options.aovs = aovs;
    if (s.denoise) options.aovs.add(AovKind::DenoiseHalves);
    RenderSettings& settings = options.settings;
    settings.width = w, settings.height = h, settings.spp = s.spp, settings.seed = seed,
    settings.progress = false;
    settings.adaptiveBatch = s.adaptiveBatch, settings.adaptiveTolerance = s.adaptiveTolerance;
    settings.sampler = s.sampler;
    RenderJob job(scene, accel, options);
    Film film = job.makeFilm();
    RenderStats stats = job.render(film);
    Rendered r{Image::fromFilm(film), stats.seconds, double(stats.samples) / (double(w) * h),
               stats.rays, job.guided()};
    if (s.denoise) {
        auto start = std::chrono::steady_clock::now();
        r.image.pixels = *denoiseFilm(film, {});
        r.image.variance.clear();
        r.seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return r;
}

uint64_t fnv(const std::string& s, uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

// The reference's AOVs: those asked for, and for the denoised sweep the albedo whose edges it
// measures (albedoEdgeContrast).
std::string referenceAovs(const AccuracyOptions& o) {
    if (!o.denoise || ("," + o.aovs + ",").find(",albedo,") != std::string::npos) return o.aovs;
    return o.aovs.empty() ? "albedo" : "albedo," + o.aovs;
}

// The reference for a depth, from the cache when its key matches, else rendered and cached as EXR.
Image reference(const Scene& scene, const Accelerator& accel, const AccuracyOptions& o, int depth,
                double& seconds, bool& cached) {
    const std::string aovs = referenceAovs(o);
    std::error_code ec;
    std::string key = o.scene + "|" + o.environmentMap + "|" +
                      std::to_string(fs::file_size(o.scene, ec)) + "|" +
                      std::to_string(fs::last_write_time(o.scene, ec).time_since_epoch().count()) +
                      "|" + std::to_string(o.width) + "x" + std::to_string(o.height) + "|" +
                      std::to_string(o.referenceSpp) + "|m" + std::to_string(depth) + "|" +
                      KILN_VERSION + "|aovs:" + aovs;
    std::string name = fmt::format("reference-m{}-{:016x}.exr", depth, fnv(key));
    std::string path = (fs::path(o.outDir) / name).string();
    ChannelImage cachedImage;
    if (readChannelImage(path, cachedImage) && cachedImage.width == o.width &&
        cachedImage.height == o.height && cachedImage.channel("variance.V") >= 0) {
        cached = true;
        std::vector<std::string> layers;
        AovLayout layout(AovRequest::parse(aovs, depth));
        for (const AovChannel& c : layout.channels())
            if (c.name.size() > 2 && c.name.compare(c.name.size() - 2, 2, ".R") == 0)
                layers.push_back(c.name.substr(0, c.name.size() - 2));
        return Image::fromChannels(cachedImage, layers);
    }
    Setting s;
    s.path.maxDepth = depth;
    s.spp = o.referenceSpp;
    RenderJobOptions options;
    options.path = s.path;
    options.aovs = AovRequest::parse("variance," + aovs, depth);
    options.settings.width = o.width, options.settings.height = o.height;
    options.settings.spp = s.spp, options.settings.seed = 999, options.settings.progress = false;
    RenderJob job(scene, accel, options);
    Film film = job.makeFilm();
    RenderStats stats = job.render(film);
    seconds += stats.seconds;
    writeExr(path, film,
             {{"scene", o.scene},
              {"spp", std::to_string(s.spp)},
              {"max_depth", std::to_string(depth)},
              {"cache_key", key}});
    return Image::fromFilm(film);
}

}  // namespace

AccuracyResult runAccuracy(const AccuracyOptions& o) {
    AccuracyResult result;
    fs::create_directories(o.outDir);
    LoadOptions load;
    load.environmentMap = o.environmentMap;
    Scene scene = loadScene(o.scene, load);
    auto embree = makeEmbreeAccelerator(scene);
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    bool cachedGi = false, cachedDirect = false;
    Image giRef = reference(scene, *embree, o, 100, result.referenceSeconds, cachedGi);
    // The denoised sweep compares full-depth renders only.
    Image directRef = o.denoise
                          ? Image{}
                          : reference(scene, *embree, o, 1, result.referenceSeconds, cachedDirect);
    cachedDirect |= o.denoise;
    result.referenceCached = cachedGi && cachedDirect;
    const RenderPlan plan = planFor(scene, *embree, AovRequest{});
    result.caustics = plan.caustics;
    double budgetStart = elapsed();
    AovRequest aovs = AovRequest::parse(o.aovs, 100);

    auto run = [&](const std::string& group, const std::string& label, const Setting& s,
                   const Image& ref) {
        // Skip a setting whose predicted time (from its spp and the time per spp so far) would
        // break the budget.
        double perSpp = 0;
        for (const AccuracyRun& a : result.runs)
            if (a.group != "denoised")  // the denoiser's time does not grow with spp
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
        a.sampling = toString(s.path.sampling);
        a.roulette = toString(s.path.roulette);
        a.accel = s.referenceAccel ? "reference" : "embree";
        a.sampler = toString(s.sampler);
        a.guided = r.guided;
        a.adaptiveTolerance = s.adaptiveTolerance;
        a.seconds = r.seconds, a.meanSpp = r.meanSpp, a.rays = r.rays;
        a.error = compareImages(r.image, ref);
        for (const std::string& layer : ref.layerNames)
            if (r.image.layer(layer))
                a.aovErrors.emplace_back(layer, compareLayer(r.image, ref, layer));
        if (const std::vector<Color>* albedo = ref.layer("albedo"))
            a.edgeContrast = albedoEdgeContrast(r.image, ref, *albedo);
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
    if (o.denoise) {
        // The denoised curve: every other spp of the raw sweep, render and denoise timed.
        for (int spp = 1; spp <= maxSpp; spp *= 4) {
            Setting s;
            s.spp = spp;
            s.denoise = true;
            run("denoised", std::to_string(spp) + " spp denoised", s, giRef);
        }
        writeAccuracyReport(o, result);
        return result;
    }
    // The same sweep with the other sampler: what the low-discrepancy sequence buys (or costs).
    SamplerKind other = RenderSettings{}.sampler == SamplerKind::Sobol ? SamplerKind::Independent
                                                                       : SamplerKind::Sobol;
    for (int spp = 1; spp <= maxSpp; spp *= (o.quick ? 4 : 2)) {
        Setting s;
        s.spp = spp;
        s.sampler = other;
        run("sampler", std::string(toString(other)) + " " + std::to_string(spp), s, giRef);
    }
    // Where the plan guides diffuse bounces, the same sweep unguided: what the guide buys.
    if (plan.guiding)
        for (int spp = 1; spp <= maxSpp; spp *= (o.quick ? 4 : 2)) {
            Setting s;
            s.spp = spp;
            s.path.guiding = GuideMode::Off;
            run("guiding", "unguided " + std::to_string(spp), s, giRef);
        }
    for (DirectSampling d :
         {DirectSampling::Hemisphere, DirectSampling::Light, DirectSampling::Mis})
        for (int spp = 1; spp <= maxSpp; spp *= (o.quick ? 4 : 2)) {
            Setting s;
            s.spp = spp;
            s.path.maxDepth = 1;
            s.path.sampling = d;
            run("strategy", std::string(toString(d)) + " " + std::to_string(spp), s, directRef);
        }
    if (o.quick) {
        writeAccuracyReport(o, result);
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
        run("adaptive", fmt::format("tol={:.4g}", tol), s, giRef);
    }
    for (bool ref : {false, true}) {
        Setting s;
        s.spp = 16;
        s.referenceAccel = ref;
        run("accel", ref ? "reference" : "embree", s, giRef);
    }
    writeAccuracyReport(o, result);
    return result;
}

}  // namespace kiln
