// kiln bench accel: build time and rays/s of both accelerators, 1 and all threads, with ratios
// measured in the same run (the machine is shared and noisy; absolute figures drift, ratios much
// less).
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "renderer/accel/reference_bvh.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/commands.h"
#include "renderer/render_job.h"
#include "renderer/validation/accuracy.h"
#include "renderer/validation/ray_sets.h"
#include "scene/importers.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

enum class Mode { Single, Packets, Shadow };

// Median of `repeats` timed passes; returns Mrays/s.
double measure(const Accelerator& accel, const std::vector<Ray>& rays, Mode mode, int threads,
               int repeats) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    std::vector<double> rates;
    for (int r = 0; r < repeats; ++r) {
        std::atomic<uint64_t> sink{0};
        double t0 = now();
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, rays.size(), 1024),
            [&](const tbb::blocked_range<size_t>& range) {
                uint64_t hits = 0;
                if (mode == Mode::Packets) {
                    std::vector<Hit> out(range.size());
                    accel.intersect(std::span<const Ray>(rays.data() + range.begin(), range.size()),
                                    std::span<Hit>(out));
                    for (const Hit& h : out) hits += h.valid();
                } else {
                    for (size_t i = range.begin(); i != range.end(); ++i) {
                        Hit h;
                        hits += mode == Mode::Shadow ? accel.occluded(rays[i])
                                                     : accel.intersect(rays[i], h);
                    }
                }
                sink += hits;
            });
        rates.push_back(double(rays.size()) / (now() - t0) * 1e-6);
    }
    std::sort(rates.begin(), rates.end());
    return rates[rates.size() / 2];
}

// CS184 student baseline (../shared/docs/CS184_BASELINE.md), primary rays, 2 threads, Mrays/s.
double cs184Baseline(const std::string& scene) {
    if (scene.find("maxplanck") != std::string::npos) return 3.6;
    if (scene.find("CBbunny.dae") != std::string::npos) return 5.7;
    return 0;
}

}  // namespace

// kiln bench plan: render time of the plan's specialised path against the general path, same run,
// alternating, median of the repeats.
int benchPlan(const std::vector<std::string>& args) {
    ArgParser parser("bench plan", "SCENE... [-s SPP] [-r W H] [-m DEPTH] [--repeats N]");
    int spp = 16, depth = 5, repeats = 3, width = 240, height = 180;
    parser.intOption("spp", "s", "samples per pixel (default 16)", spp, 1, 1 << 16);
    parser.intOption("max-depth", "m", "CS184 depth (default 5)", depth, 0, 1000);
    parser.intOption("repeats", "", "timed renders of each path, median reported (default 3)",
                     repeats, 1, 50);
    parser.option("resolution", "r", 2, "W H", "image size (default 240 180)",
                  [&](const std::vector<std::string>& v) {
                      width = ArgParser::toInt("-r", v[0], 1, 8192);
                      height = ArgParser::toInt("-r", v[1], 1, 8192);
                  });
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.empty()) throw UsageError("needs at least one scene file");
    std::printf("%-32s %-44s %10s %10s %8s\n", "scene", "plan", "special s", "general s",
                "speed-up");
    for (const std::string& path : pos) {
        Scene scene = loadScene(path);
        auto accel = makeEmbreeAccelerator(scene);
        // kiln render's defaults (AOVs included) but for the plan mode.
        RenderJobOptions options;
        options.path.maxDepth = depth;
        options.settings.width = width, options.settings.height = height;
        options.settings.spp = spp, options.settings.progress = false;
        std::vector<std::unique_ptr<RenderJob>> jobs;
        for (PlanMode mode : {PlanMode::Auto, PlanMode::General}) {
            options.plan = mode;
            jobs.push_back(std::make_unique<RenderJob>(scene, *accel, options));
        }
        std::vector<double> times[2];
        for (int r = 0; r < repeats; ++r)
            for (int k = 0; k < 2; ++k) {
                Film film = jobs[size_t(k)]->makeFilm();
                times[k].push_back(jobs[size_t(k)]->render(film).seconds);
            }
        for (auto& t : times) std::sort(t.begin(), t.end());
        double special = times[0][times[0].size() / 2], general = times[1][times[1].size() / 2];
        std::string name = path.substr(path.find_last_of('/') + 1);
        std::printf("%-32s %-44s %10.3f %10.3f %7.2fx\n", name.c_str(),
                    jobs[0]->plan().compact().c_str(), special, general, general / special);
        std::fflush(stdout);
    }
    std::printf(
        "\n%dx%d, %d spp, -m %d, median of %d alternating renders per path; speed-up = general / "
        "special\n",
        width, height, spp, depth, repeats);
    return 0;
}

// kiln bench scale: what big scenes cost. One row per scene; run one scene per process for a
// meaningful peak-memory column (tools/scale_report.sh does).
int benchScale(const std::vector<std::string>& args) {
    ArgParser parser("bench scale", "SCENE... [--compare-assimp]");
    bool compareAssimp = false;
    parser.flag("compare-assimp", "",
                "also time Assimp's import of each OBJ/PLY file (the direct readers' baseline)",
                compareAssimp);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.empty()) throw UsageError("needs at least one scene file");
    std::printf("%-28s %12s %12s %8s %8s %9s %9s %9s %9s %9s\n", "scene", "triangles", "stored",
                "load s", "build s", "bytes/tri", "prim 1", "prim pkt", "path Mr/s", "peak GiB");
    for (const std::string& path : pos) {
        double t0 = now();
        Scene scene = loadScene(path);
        double load = now() - t0;
        auto accel = makeEmbreeAccelerator(scene);
        uint64_t stored = std::max<uint64_t>(1, scene.uniqueTriangles());
        double bytes =
            double(accel->stats().memoryBytes + summarize(scene).geometryBytes) / double(stored);
        std::vector<Ray> primary = makeCoherentCameraRays(scene, 800, 600, 400000);
        int threads = int(std::thread::hardware_concurrency());
        // Camera rays one at a time (as the render loop traces them) and as 16-wide packets.
        double primSingle = measure(*accel, primary, Mode::Single, threads, 3);
        double primPackets = measure(*accel, primary, Mode::Packets, threads, 3);
        // Path tracing: the median of at least three renders and two seconds of rendering (a
        // small mesh renders in 0.1 s, and single short renders swing by a third on a shared
        // machine).
        // kiln render's defaults at 320x240, 16 spp.
        RenderJobOptions options;
        options.settings.width = 320, options.settings.height = 240;
        options.settings.spp = 16, options.settings.progress = false;
        RenderJob job(scene, *accel, options);
        std::vector<double> pathRates;
        for (double rendered = 0; pathRates.size() < 3 || rendered < 2.0;) {
            Film film = job.makeFilm();
            RenderStats stats = job.render(film);
            pathRates.push_back(double(stats.rays) / stats.seconds * 1e-6);
            rendered += stats.seconds;
        }
        std::sort(pathRates.begin(), pathRates.end());
        struct rusage usage {};
        getrusage(RUSAGE_SELF, &usage);
        std::string name = path.substr(path.find_last_of('/') + 1);
        std::printf("%-28s %12llu %12llu %8.2f %8.2f %9.1f %9.2f %9.2f %9.2f %9.2f\n", name.c_str(),
                    (unsigned long long)scene.instancedTriangles(),
                    (unsigned long long)scene.uniqueTriangles(), load, accel->stats().buildSeconds,
                    bytes, primSingle, primPackets, pathRates[pathRates.size() / 2],
                    double(usage.ru_maxrss) / (1024.0 * 1024.0));
        if (compareAssimp && path.find(".kiln") == std::string::npos) {
            double a0 = now();
            Scene viaAssimp;
            importWithAssimp(path, nullptr, viaAssimp);
            double assimp = now() - a0;
            std::printf("%-28s Assimp import %.2f s, %.1fx the direct reader's load\n", "", assimp,
                        assimp / load);
        }
        std::fflush(stdout);
    }
    return 0;
}

// kiln bench compare: the accuracy report's error statistics for any two images (e.g. another
// renderer's render against its own converged reference, for tools/peer_bench.py).
int benchCompare(const std::vector<std::string>& args) {
    ArgParser parser("bench compare", "TEST.exr REFERENCE.exr [--keep-reference-noise]");
    bool keepNoise = false;
    parser.flag("keep-reference-noise", "",
                "do not subtract the reference's own variance (its 'variance' channel) from the "
                "squared errors: treats a kiln reference like one without that channel",
                keepNoise);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 2) throw UsageError("needs a test image and a reference image");
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        ChannelImage file;
        if (!readChannelImage(pos[size_t(i)], file) || file.channelNames.size() < 3)
            throw UsageError(pos[size_t(i)] + ": cannot read an RGB image");
        images[i] = Image::fromChannels(file);
    }
    if (images[0].width != images[1].width || images[0].height != images[1].height)
        throw UsageError(pos[0] + ": " + std::to_string(images[0].width) + "x" +
                         std::to_string(images[0].height) + ", the reference is " +
                         std::to_string(images[1].width) + "x" + std::to_string(images[1].height));
    if (keepNoise) images[1].variance.clear();
    ErrorStats e = compareImages(images[0], images[1]);
    std::printf("relmse %.6g rmse %.6g bias %.6g reference_mean %.6g\n", e.relMse, e.rmse, e.bias,
                e.referenceMean);
    return 0;
}

int runBench(const std::vector<std::string>& args) {
    if (!args.empty() && args[0] == "scale")
        return benchScale(std::vector<std::string>(args.begin() + 1, args.end()));
    if (!args.empty() && args[0] == "plan")
        return benchPlan(std::vector<std::string>(args.begin() + 1, args.end()));
    if (!args.empty() && args[0] == "compare")
        return benchCompare(std::vector<std::string>(args.begin() + 1, args.end()));
    if (!args.empty() && args[0] == "accuracy")
        return runAccuracyCommand(std::vector<std::string>(args.begin() + 1, args.end()));
    if (args.empty() || (args[0] != "accel" && args[0] != "-h" && args[0] != "--help"))
        throw UsageError(
            "usage: kiln bench accel|plan|scale|accuracy SCENE..., kiln bench compare TEST REF "
            "(see 'kiln "
            "bench accel --help', 'kiln "
            "bench plan --help')");
    ArgParser parser("bench accel", "SCENE... [--rays N] [--repeats N] [--threads N]");
    int rays = 200000, repeats = 3, threads = int(std::thread::hardware_concurrency());
    AcceleratorChoice choice;
    parser.intOption("rays", "", "rays per measurement (default 200000)", rays, 1000, 1 << 28);
    parser.intOption("repeats", "", "timed passes, median reported (default 3)", repeats, 1, 100);
    parser.intOption("threads", "t", "the 'all threads' column (default: all cores)", threads, 1,
                     4096);
    choice.addOptions(parser, false);
    std::vector<std::string> pos =
        parser.parse(std::vector<std::string>(args.begin() + (args[0] == "accel"), args.end()));
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.empty()) throw UsageError("needs at least one scene file");

    std::string statsTable;
    std::printf("%-26s %9s %-9s %8s %8s %8s %8s %8s %8s %8s %8s\n", "scene", "tris", "accel",
                "build s", "prim 1t", "prim Nt", "pkt Nt", "incoh Nt", "shdw Nt", "emb/ref",
                "vs CS184");
    for (const std::string& path : pos) {
        Scene scene = loadScene(path);
        auto embree = makeEmbreeAccelerator(scene, choice.embree);
        auto referenceBvh = std::make_unique<ReferenceAccelerator>(scene, choice.reference);
        const ReferenceAccelerator& ref = *referenceBvh;
        std::unique_ptr<Accelerator> reference = std::move(referenceBvh);
        std::vector<Ray> primary = makeCoherentCameraRays(scene, 800, 600, size_t(rays));
        std::vector<Ray> incoherent =
            makeRaySet(RaySetKind::Random, scene, *embree, size_t(rays), 7);
        std::vector<Ray> shadow = makeRaySet(RaySetKind::Shadow, scene, *embree, size_t(rays), 7);
        double rate[2][5];
        const Accelerator* accels[2] = {embree.get(), reference.get()};
        for (int a = 0; a < 2; ++a) {
            rate[a][0] = measure(*accels[a], primary, Mode::Single, 1, repeats);
            rate[a][1] = measure(*accels[a], primary, Mode::Single, threads, repeats);
            rate[a][2] = measure(*accels[a], primary, Mode::Packets, threads, repeats);
            rate[a][3] = measure(*accels[a], incoherent, Mode::Single, threads, repeats);
            rate[a][4] = measure(*accels[a], shadow, Mode::Shadow, threads, repeats);
        }
        std::string name = path.substr(path.find_last_of('/') + 1);
        // Reference BVH work per ray, counted on the same ray sets.
        BvhStatistics bs = ref.topLevelStatistics();
        double perRay[2][2];
        const std::vector<Ray>* sets[2] = {&primary, &incoherent};
        for (int k = 0; k < 2; ++k) {
            TraversalCounters counters;
            for (const Ray& r : *sets[k]) {
                Hit h;
                ref.intersect(r, h, counters);
            }
            perRay[k][0] = double(counters.boxTests) / double(sets[k]->size());
            perRay[k][1] = double(counters.primTests) / double(sets[k]->size());
        }
        statsTable +=
            fmt::format("{:<26} {:>9} {:>6} {:>6} {:8.2f} {:8.1f} {:8.1f} {:8.1f} {:8.1f}\n", name,
                        bs.nodes, bs.leaves, bs.maxDepth, bs.sahCost, perRay[0][0], perRay[0][1],
                        perRay[1][0], perRay[1][1]);
        double base = cs184Baseline(path);
        for (int a = 0; a < 2; ++a) {
            std::string ratio, vs;
            if (a == 0) ratio = fmt::format("{:.2f}x", rate[0][1] / rate[1][1]);
            if (base > 0 && a == 0)
                vs = fmt::format("{:.1f}x", std::max(rate[0][1], rate[0][2]) / base);
            fmt::print(
                "{:<26} {:>9} {:<9} {:8.3f} {:8.2f} {:8.2f} {:8.2f} {:8.2f} {:8.2f} {:>8} {:>8}\n",
                a == 0 ? name : "", scene.instancedTriangles(),
                toString(a == 0 ? AcceleratorKind::Embree : AcceleratorKind::Reference),
                accels[a]->stats().buildSeconds, rate[a][0], rate[a][1], rate[a][2], rate[a][3],
                rate[a][4], ratio, vs);
        }
        std::fflush(stdout);
    }
    std::printf(
        "\nreference BVH (%s): structure and work per ray\n%-26s %9s %6s %6s %8s %8s %8s %8s "
        "%8s\n%s",
        ReferenceAccelerator(Scene{}, choice.reference).stats().description.c_str(), "scene",
        "nodes", "leaves", "depth", "SAH", "box/prim", "tri/prim", "box/inc", "tri/inc",
        statsTable.c_str());
    std::printf(
        "\nrates in Mrays/s (median of %d); Nt = %d threads; prim = camera rays in 4x4 blocks at "
        "800x600, one\n"
        "at a time; pkt = the same rays as 16-wide packets (reference: a loop); incoh = random "
        "rays through\n"
        "the bounds; shdw = shadow rays from surface points to lights; emb/ref = Embree over "
        "reference,\n"
        "single primary rays Nt; vs CS184 = Embree's best primary rate over the CS184 baseline\n"
        "(maxplanck 3.6, CBbunny 5.7 Mrays/s at 2 threads)\n",
        repeats, threads);
    return 0;
}

}  // namespace kiln
