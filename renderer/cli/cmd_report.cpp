// kiln report cs184: the CS184 PathTracer write-up (the course's five parts and their tasks, in
// order, with its headings) for the given scenes: every image made by the kiln render command
// its caption shows, sized to a time budget (cs184_planner.h), each figure discussed in words
// filled with what this run measured (cs184_prose.h), as HTML or Markdown with its images beside
// it, plus report.json with every command and measurement.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "color/atomic_file.h"
#include "renderer/accel/brute_force.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/cs184_planner.h"
#include "renderer/cli/cs184_prose.h"
#include "renderer/cli/report_page.h"
#include "renderer/core/json.h"
#include "renderer/core/log.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using namespace cs184;
using Clock = std::chrono::steady_clock;

// A timed render shorter than this is mostly the timer's and the thread pool's noise.
constexpr double kTimingFloorSeconds = 0.25;

struct ReportOptions {
    std::vector<std::string> scenes;
    std::vector<std::string> bvhScenes;  // empty: the course's, found beside the first scene
    bool noBvhScenes = false;
    std::string dir;
    double budget = 300;  // seconds for the whole report
    int threads = 0;
    std::string view = "CS184";
    PageFormat format = PageFormat::Html;
    std::string commandLine;
    Clock::time_point start = Clock::now();
};

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string one, five, fifteen;
    in >> one >> five >> fifteen;
    return one.empty() ? "unknown" : one + " " + five + " " + fifteen;
}

// The prefix of a scene's image files: its name in safe characters, numbered from the second scene
// on, so two scenes of one name (or a name with '#' or '?') cannot clash or break a link.
std::string imageStem(const std::string& scenePath, size_t index) {
    std::string stem = fs::path(scenePath).stem().string();
    for (char& c : stem)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    return index == 0 ? stem : stem + "_" + std::to_string(index + 1);
}

// The course's BVH meshes (cow, maxplanck, CBlucy) in the course's library the first scene is in
// (its folders meshedit/ and sky/).
std::vector<std::string> courseBvhMeshes(const std::string& firstScene) {
    fs::path library = fs::path(firstScene).parent_path().parent_path();
    return {(library / "meshedit" / "cow.dae").string(),
            (library / "meshedit" / "maxplanck.dae").string(),
            (library / "sky" / "CBlucy.dae").string()};
}

struct SceneReport {
    std::string path, stem;
    Scene scene;
    std::unique_ptr<Accelerator> embree;
};

class Cs184Report {
  public:
    explicit Cs184Report(const ReportOptions& o)
        : o_(o),
          figures_(courseFigures()),
          planner_(figures_, o.scenes.size()),
          page_("CS184 PathTracer write-up, rendered by kiln") {}
    void run();

  private:
    ShotRunner runner(const SceneReport& s) const {
        return ShotRunner(s.scene, *s.embree, s.path, o_.dir, o_.threads, o_.view);
    }
    double secondsLeft() const { return o_.budget - secondsSince(o_.start); }
    // Embree's build kept to -t as a render's is (it would otherwise take every core).
    std::unique_ptr<Accelerator> buildEmbree(const Scene& scene) const {
        return makeEmbreeAccelerator(scene, AcceleratorChoice{}.withThreads(o_.threads).embree);
    }
    // Kept back from the sweep's top images, the last ones: the page, the JSON, and the error of
    // their own time estimate (a busier machine makes them slower than the last render said).
    double topReserve() const { return 1.0 + 0.03 * o_.budget; }
    void timeBvh();
    void timeMesh(const std::string& path);
    ShotResult timedRender(const ShotRunner& r, const std::string& accel, const std::string& file,
                           bool crop, double allowed, double fullEstimate, double& covered,
                           int& spp);
    void probe(size_t scene);
    void renderFigure(size_t f, double scale, bool topOnly);
    void record(size_t scene, const ShotResult& r, const std::string& flags);
    void writePage();
    void writeHeader();
    void writeBvhTable();
    void writeFigure(size_t f);
    void writeJson() const;
    std::string caption(const Shot& shot, const ShotPlan& plan, const ShotResult& r) const;

    const ReportOptions& o_;
    std::vector<Figure> figures_;
    Planner planner_;
    ReportPage page_;
    std::vector<SceneReport> scenes_;
    Size size_{0, 0};
    double needMain_ = 0;  // the budget the main size needs, estimated at the start
    std::string loadStart_;
    size_t embreeThreads_ = 0;  // TBB's bound while the accelerators were built
    std::vector<TimingRow> timings_;
    std::vector<std::string> missingMeshes_;
    std::vector<ShotResult> probes_;
    // results_[figure][scene][shot]; plans_ likewise; scales_[figure]
    std::vector<std::vector<std::vector<ShotResult>>> results_;
    std::vector<std::vector<std::vector<ShotPlan>>> plans_;
    std::vector<double> scales_;
    std::vector<Film> references_;  // per scene: the importance figure's film (lightrays' noise)
};

void Cs184Report::record(size_t scene, const ShotResult& r, const std::string& flags) {
    planner_.throughput(scene).record(sppFreeKey(flags), double(r.stats.rays), r.wallSeconds);
}

// One timed normal-shading render of the course's 800x600 frame; below the timer floor it is run
// again with more samples. Brute force renders a band of the frame: first one its estimate puts
// at twice the floor, then, from the speed that band measured, one that takes the allowed time.
ShotResult Cs184Report::timedRender(const ShotRunner& r, const std::string& accel,
                                    const std::string& file, bool crop, double allowed,
                                    double fullEstimate, double& covered, int& spp) {
    double fraction = crop ? std::min(1.0, 2 * kTimingFloorSeconds / fullEstimate) : 1.0;
    spp = 1;
    for (int attempt = 0;; ++attempt) {
        std::string flags = "-i normals -s " + std::to_string(spp) + " " + accel;
        if (fraction < 1) {
            int rows = std::max(1, int(std::ceil(fraction * kCourseHeight)));
            int top = (kCourseHeight - rows) / 2;
            flags += fmt::format(" --crop 0 1 {:.6g} {:.6g}", double(top) / kCourseHeight,
                                 double(top + rows) / kCourseHeight);
        }
        ShotResult res = r.run(flags, kCourseWidth, kCourseHeight, file);
        covered = double(res.stats.samples) / spp;
        const double seconds = std::max(res.stats.seconds, 1e-4);
        const double frameSeconds = seconds * kCourseWidth * kCourseHeight / covered;
        const double wanted = crop ? std::min(1.0, allowed / frameSeconds) : 1.0;
        if (attempt == 4) return res;
        if (crop && fraction < 1 && wanted > 1.5 * fraction)
            fraction = wanted;
        else if (seconds < kTimingFloorSeconds && crop && fraction < 1)
            fraction = std::min(1.0, fraction * 1.5 * kTimingFloorSeconds / seconds);
        else if (seconds < kTimingFloorSeconds && !crop)
            spp = std::min(1024, spp * int(std::ceil(1.5 * kTimingFloorSeconds / seconds)));
        else
            return res;
    }
}

void Cs184Report::timeMesh(const std::string& path) {
    if (!fs::exists(path)) {
        missingMeshes_.push_back(path);
        return;
    }
    Scene scene = loadScene(path);
    auto built = Clock::now();
    auto embree = buildEmbree(scene);
    const double embreeBuild = secondsSince(built);
    ShotRunner r(scene, *embree, path, o_.dir, o_.threads, o_.view);
    std::string stem = imageStem(path, 0);
    const double frame = double(kCourseWidth) * kCourseHeight;
    double estimate = bruteForceSeconds(
        scene, jobForFlags(fmt::format("-i normals -s 1 -r {} {}{}", kCourseWidth, kCourseHeight,
                                       o_.threads ? " -t " + std::to_string(o_.threads) : "")));
    // Brute force gets a thirtieth of the budget per mesh, never less than twice the floor.
    double allowed = std::max(2 * kTimingFloorSeconds, o_.budget / 30);
    struct Kind {
        const char *name, *flags, *file;
        bool crop;
    };
    for (Kind k : {Kind{"Embree (kiln's default)", "", "_embree.png", false},
                   Kind{"reference BVH, the course's split", "--accel reference --bvh-split mean",
                        "_bvh.png", false},
                   Kind{"no BVH", "--accel brute", "_brute.png", true}}) {
        TimingRow row;
        row.mesh = fs::path(path).filename().string();
        row.traversal = k.name;
        row.primitives = bruteForcePrimitiveCount(scene);
        row.fullFramePixels = frame;
        row.shot = timedRender(r, k.flags, stem + k.file, k.crop, allowed, estimate,
                               row.coveredPixels, row.spp);
        if (std::string(k.flags).empty()) row.shot.buildSeconds = embreeBuild;
        timings_.push_back(row);
    }
}

void Cs184Report::timeBvh() {
    if (o_.noBvhScenes) return;
    for (const std::string& path :
         o_.bvhScenes.empty() ? courseBvhMeshes(o_.scenes[0]) : o_.bvhScenes)
        timeMesh(path);
}

// What the planner needs of a scene before the size is chosen: the rays a camera sample of each
// flag set of the figures traces (an 80x60 render at 1 sample per pixel each), and the seconds a
// ray costs (a global illumination render large enough to hide the set-up). Its files go.
void Cs184Report::probe(size_t scene) {
    ShotRunner r = runner(scenes_[scene]);
    const std::string file = scenes_[scene].stem + "_probe.png";
    std::set<std::string> keys;
    for (const Figure& f : figures_)
        for (const Shot& s : f.shots)
            if (s.layer.empty()) keys.insert(sppFreeKey(planShot(s, 1, s.courseSpp).flags));
    for (const std::string& key : keys) {
        ShotResult p = r.run("-s 1 " + key, 80, 60, file);
        planner_.throughput(scene).setRaysPerSample(
            key, double(p.stats.rays) / double(std::max<uint64_t>(1, p.stats.samples)));
    }
    const std::string flags = "-s 4 -l 4 -m 5";
    ShotResult speed = r.run(flags, 160, 120, file);
    record(scene, speed, flags);
    probes_.push_back(speed);
    std::error_code ignored;
    fs::remove(fs::path(o_.dir) / file, ignored);
}

std::string Cs184Report::caption(const Shot& shot, const ShotPlan& plan,
                                 const ShotResult& r) const {
    std::string text = shot.label + ": " + fixed(r.stats.seconds, 2) + " s, " +
                       fmt::format("{:.3g}", double(r.stats.rays) * 1e-6) + " Mrays";
    std::string course = "-s " + std::to_string(shot.courseSpp);
    if (shot.courseBatch > 0)
        course +=
            " -a " + std::to_string(shot.courseBatch) + " " + fmt::format("{}", shot.tolerance);
    std::string here = "-s " + std::to_string(plan.spp);
    if (plan.batch > 0)
        here += " -a " + std::to_string(plan.batch) + " " + fmt::format("{}", shot.tolerance);
    if (here != course) {
        text += "; the course uses " + course + ", this run " + here;
        if (shot.rule == SppRule::Top)
            text += ": what the budget left";
        else
            text += ": the budget";
        if (plan.batch > 0 && plan.batch != shot.courseBatch)
            text += "; the batch is a quarter of the cap so that pixels can stop before it";
    }
    return text;
}

void Cs184Report::renderFigure(size_t f, double scale, bool topOnly) {
    const Figure& fig = figures_[f];
    int top = nominalTop(fig, scale);
    scales_[f] = scale;
    for (size_t s = 0; s < scenes_.size(); ++s) {
        ShotRunner r = runner(scenes_[s]);
        auto& results = results_[f][s];
        auto& plans = plans_[f][s];
        results.resize(fig.shots.size()), plans.resize(fig.shots.size());
        Film kept(1, 1);
        for (size_t i = 0; i < fig.shots.size(); ++i) {
            const Shot& shot = fig.shots[i];
            if ((shot.rule == SppRule::Top) != topOnly) continue;
            if (shot.rule == SppRule::Top) {
                // What the budget has left, shared by the scenes whose top is still to render.
                int floorSpp = 1;
                for (const ShotPlan& p : plans)
                    if (p.spp > 0) floorSpp = std::max(floorSpp, p.spp);
                double seconds = (secondsLeft() - topReserve()) / double(scenes_.size() - s);
                top = planner_.topSpp(s, shot, size_, seconds, floorSpp);
            }
            if (!shot.layer.empty()) {
                results[i] = results[i - 1];
                results[i].file = scenes_[s].stem + "_" + shot.id + ".png";
                results[i].image = r.writeLayer(kept, shot.layer, results[i].file);
                plans[i] = plans[i - 1];
                continue;
            }
            plans[i] = planShot(shot, scale, top);
            if (plans[i].spp == 0) continue;
            results[i] = r.run(plans[i].flags, size_.width, size_.height,
                               scenes_[s].stem + "_" + shot.id + ".png", &kept);
            record(s, results[i], plans[i].flags);
            if (fig.key == "importance") references_[s] = std::move(kept);
            if (fig.key == "lightrays")
                results[i].image.noise = medianRelativeDifference(kept, references_[s]);
            logInfo("report: {} {} {:.1f} s ({:.0f} s left)", scenes_[s].stem, shot.id,
                    results[i].wallSeconds, secondsLeft());
        }
    }
}

// Cheap figures at the course's setting first, then adaptive sampling (its cost is known only
// once it ran), then the scaled figures, the sweep's steps, and the sweep's top last.
std::vector<size_t> renderOrder(const std::vector<Figure>& figures) {
    auto rank = [&](size_t f) {
        int r = 0;
        for (const Shot& s : figures[f].shots)
            r = std::max(r, s.rule == SppRule::Course   ? 0
                            : s.courseBatch > 0         ? 1
                            : s.rule == SppRule::Scaled ? 2
                                                        : 3);
        return r;
    };
    std::vector<size_t> order(figures.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return rank(a) < rank(b); });
    return order;
}

void Cs184Report::run() {
    loadStart_ = loadAverage();
    // Every scene loaded first: a bad file is refused before any rendering.
    for (const std::string& path : o_.scenes) {
        SceneReport s;
        s.path = path;
        s.stem = imageStem(path, scenes_.size());
        s.scene = loadScene(path);
        scenes_.push_back(std::move(s));
    }
    for (SceneReport& s : scenes_) s.embree = buildEmbree(s.scene);
    // What Embree's builds were kept to, read back while the accelerators hold it (report.json).
    embreeThreads_ =
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    timeBvh();
    for (size_t s = 0; s < scenes_.size(); ++s) probe(s);
    const double reserve = 1.0 + 0.01 * o_.budget;  // the page, the JSON, the last refit's error
    size_ = planner_.chooseSize(secondsLeft() - reserve);
    needMain_ = secondsSince(o_.start) + planner_.secondsNeeded(kMainSize) + reserve;
    logInfo("report: {}x{} ({:.0f} s left; {}x{} needs a budget of about {:.0f} s)", size_.width,
            size_.height, secondsLeft(), kMainSize.width, kMainSize.height, needMain_);
    results_.assign(figures_.size(), std::vector<std::vector<ShotResult>>(scenes_.size()));
    plans_.assign(figures_.size(), std::vector<std::vector<ShotPlan>>(scenes_.size()));
    scales_.assign(figures_.size(), 0);
    for (size_t s = 0; s < scenes_.size(); ++s) references_.emplace_back(1, 1);
    std::vector<size_t> order = renderOrder(figures_);
    for (size_t i = 0; i < order.size(); ++i) {
        std::vector<size_t> remaining(order.begin() + long(i), order.end());
        double scale = planner_.fitScale(remaining, size_, secondsLeft() - reserve);
        renderFigure(order[i], scale, false);
    }
    for (size_t f = 0; f < figures_.size(); ++f)
        for (const Shot& s : figures_[f].shots)
            if (s.rule == SppRule::Top) renderFigure(f, scales_[f], true);
    writePage();
    writeJson();
    logInfo("report: {} s of a {} s budget", fixed(secondsSince(o_.start), 1), fixed(o_.budget, 0));
}

// The page's opening: how it was made, the budget and the load, how sizes and samples were chosen.
void Cs184Report::writeHeader() {
    double total = secondsSince(o_.start);
    page_.paragraph(fmt::format(
        "Made by: {}. It took {} s of a {} s budget ({:.0f} %); load average {} at the start and "
        "{} at the end (1, 5 and 15 minutes; the machine is shared, so times are noisy).",
        o_.commandLine, fixed(total, 1), fixed(o_.budget, 0), 100 * total / o_.budget, loadStart_,
        loadAverage()));
    std::string probes;
    for (size_t s = 0; s < probes_.size(); ++s)
        probes += fmt::format("{}{}: {:.2f} Mrays/s", s ? ", " : "", scenes_[s].stem,
                              double(probes_[s].stats.rays) / probes_[s].stats.seconds * 1e-6);
    page_.paragraph(fmt::format(
        "Images are {}x{}: the report measured the rays a camera sample of each figure's flags "
        "traces (an 80x60 render at 1 sample per pixel each) and the scenes' speed (160x120, "
        "-s 4 -l 4 -m 5: {}), and chose the largest 4:3 size at which every figure fits the budget "
        "with at least 1/{:.0f} "
        "of the course's samples; then, before every figure, it fitted the samples to the time "
        "left from the speed measured so far. {}x{} needs a budget of about {:.0f} s at the "
        "speed measured at the start. Each caption is the kiln render command that made the "
        "image: the report parses it with kiln render's own parser and renders it on the scene "
        "loaded once; run from the same directory it writes the same PNG (and an EXR beside it, "
        "which the report does not keep). Images are shown with the OCIO view '{}'{}.",
        size_.width, size_.height, probes, 1 / kMinScale, kMainSize.width, kMainSize.height,
        needMain_, o_.view,
        o_.view == "CS184" ? " (the course's display: sqrt(2) exposure, gamma 2.2)" : ""));
}

// Part 2, task 3: the BVH timing table, the meshes' images and what the timings show.
void Cs184Report::writeBvhTable() {
    std::vector<std::vector<std::string>> rows;
    std::vector<ReportPage::Image> images;
    for (const TimingRow& row : timings_) {
        rows.push_back(
            {row.mesh, row.traversal, fixed(row.shot.buildSeconds, 4),
             fixed(row.shot.stats.seconds, 3),
             fmt::format("{:.3g}", double(row.shot.stats.rays) / row.shot.stats.seconds * 1e-6),
             fixed(row.frameSeconds(), 3), row.shot.command});
        if (row.traversal.rfind("Embree", 0) == 0)
            images.push_back({row.shot.file,
                              row.mesh + ", normal shading at 800x600 (" +
                                  std::to_string(row.primitives) + " primitives)",
                              row.shot.command});
    }
    for (const std::string& m : missingMeshes_)
        rows.push_back({fs::path(m).filename().string(), "not timed", "-", "-", "-", "-",
                        m + " is not in the scene library"});
    if (rows.empty())
        page_.paragraph("No BVH timing: this report was made with --bvh-scenes none.");
    else
        page_.table({"mesh", "traversal", "build s", "render s", "Mrays/s", "s per 800x600 frame",
                     "command"},
                    rows);
    page_.images(images);
    for (const std::string& p : timingProse(timings_, kTimingFloorSeconds)) page_.paragraph(p);
}

// One figure: a row of images per scene, then the paragraphs that discuss them.
void Cs184Report::writeFigure(size_t f) {
    const Figure& fig = figures_[f];
    page_.heading(4, fig.title);
    std::vector<SceneShots> discussed;
    for (size_t s = 0; s < scenes_.size(); ++s) {
        std::vector<ReportPage::Image> row;
        SceneShots shots{fs::path(scenes_[s].path).filename().string(), {}};
        for (size_t i = 0; i < fig.shots.size(); ++i) {
            const ShotPlan& plan = plans_[f][s][i];
            const ShotResult& r = results_[f][s][i];
            if (plan.spp == 0) continue;
            std::string command = r.command;
            if (!fig.shots[i].layer.empty())
                command += "  (the " + fig.shots[i].layer + " layer of its EXR)";
            row.push_back({r.file, caption(fig.shots[i], plan, r), command});
            if (!r.rateFile.empty())
                row.push_back({r.rateFile,
                               fmt::format("sample rate: {:.1f} samples per pixel on "
                                           "average, {} to {}",
                                           r.image.meanSpp, r.image.minSpp, r.image.maxSpp),
                               r.command + "  (its .samples.png)"});
            shots.shots.push_back(r);
        }
        page_.images(row);
        discussed.push_back(shots);
    }
    for (const std::string& p : figureProse(fig, discussed)) page_.paragraph(p);
    if (fig.key == "importance") {
        std::vector<SceneShots> hemisphere;
        for (size_t g = 0; g < figures_.size(); ++g)
            if (figures_[g].key == "hemisphere")
                for (size_t s = 0; s < scenes_.size(); ++s)
                    hemisphere.push_back(
                        {fs::path(scenes_[s].path).filename().string(), results_[g][s]});
        for (const std::string& p : directComparison(hemisphere, discussed)) page_.paragraph(p);
    }
}

void Cs184Report::writePage() {
    writeHeader();
    for (const Task& t : courseTasks()) {
        page_.heading(t.task == 0 ? 2 : 3, t.heading);
        if (std::string intro = taskIntro(t.part, t.task); !intro.empty()) page_.paragraph(intro);
        if (t.part == 2 && t.task == 3) writeBvhTable();
        for (size_t f = 0; f < figures_.size(); ++f)
            if (figures_[f].part == t.part && figures_[f].task == t.task) writeFigure(f);
    }
    const char* name = o_.format == PageFormat::Html ? "index.html" : "index.md";
    page_.write((fs::path(o_.dir) / name).string(), o_.format);
}

Json shotJson(const ShotResult& r) {
    return {{"command", r.command},          {"file", r.file},
            {"rate_file", r.rateFile},       {"seconds", r.stats.seconds},
            {"wall_seconds", r.wallSeconds}, {"rays", r.stats.rays},
            {"samples", r.stats.samples},    {"spp", r.spp},
            {"mean_spp", r.image.meanSpp},   {"min_spp", r.image.minSpp},
            {"max_spp", r.image.maxSpp},     {"mean_luminance", r.image.meanLuminance},
            {"noise", r.image.noise}};
}

void Cs184Report::writeJson() const {
    Json shots = Json::array(), timings = Json::array();
    for (size_t f = 0; f < figures_.size(); ++f)
        for (size_t s = 0; s < scenes_.size(); ++s)
            for (size_t i = 0; i < figures_[f].shots.size(); ++i) {
                if (plans_[f][s][i].spp == 0) continue;
                Json j = shotJson(results_[f][s][i]);
                j["figure"] = figures_[f].key;
                j["layer"] = figures_[f].shots[i].layer;
                j["course_spp"] = figures_[f].shots[i].courseSpp;
                j["batch"] = plans_[f][s][i].batch;
                shots.push_back(j);
            }
    for (const TimingRow& row : timings_) {
        Json j = shotJson(row.shot);
        j["mesh"] = row.mesh;
        j["traversal"] = row.traversal;
        j["frame_seconds"] = row.frameSeconds();
        timings.push_back(j);
    }
    Json doc = {{"command", o_.commandLine},
                {"budget", o_.budget},
                {"seconds", secondsSince(o_.start)},
                {"load_average_start", loadStart_},
                {"load_average_end", loadAverage()},
                {"width", size_.width},
                {"height", size_.height},
                {"budget_for_480x360", needMain_},
                {"timing_floor_seconds", kTimingFloorSeconds},
                {"threads", o_.threads},
                {"embree_build_threads", embreeThreads_},
                {"shots", shots},
                {"timings", timings}};
    writeFileAtomically((fs::path(o_.dir) / "report.json").string(), jsonText(doc) + "\n");
}

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    for (size_t comma; (comma = text.find(',', start)) != std::string::npos; start = comma + 1)
        out.push_back(text.substr(start, comma - start));
    out.push_back(text.substr(start));
    return out;
}

}  // namespace

int runReport(const std::vector<std::string>& args) {
    if (args.empty() || args[0] != "cs184")
        throw UsageError("usage: kiln report cs184 SCENE... -o DIR [--budget SECONDS]");
    ReportOptions o;
    ArgParser parser("report cs184",
                     "SCENE... -o DIR [--budget SECONDS] [-t N] [--view NAME] [--format html|md] "
                     "[--bvh-scenes LIST]   (DIR/index.html or DIR/index.md, DIR/report.json)");
    parser.option("output", "o", 1, "DIR", "directory for the page and its images (created)",
                  [&o](const std::vector<std::string>& v) { o.dir = v[0]; });
    parser.option("budget", "", 1, "SECONDS",
                  "time for the whole report (default 300): sets the image size and samples",
                  [&o](const std::vector<std::string>& v) {
                      o.budget = ArgParser::toDouble("--budget", v[0]);
                      if (!(o.budget >= 5 && o.budget <= 7 * 86400))
                          throw UsageError("--budget must be between 5 and 604800 seconds");
                  });
    parser.intOption("threads", "t", "worker threads (default: all cores)", o.threads, 1, 4096);
    parser.option("view", "", 1, "NAME", "OCIO view of the images (default CS184)",
                  [&o](const std::vector<std::string>& v) { o.view = v[0]; });
    parser.option("format", "", 1, "html|md",
                  "the page as HTML (default) or Markdown (for a course page repository)",
                  [&o](const std::vector<std::string>& v) {
                      if (v[0] != "html" && v[0] != "md")
                          throw UsageError("--format takes html or md, got '" + v[0] + "'");
                      o.format = v[0] == "md" ? PageFormat::Markdown : PageFormat::Html;
                  });
    parser.option("bvh-scenes", "", 1, "LIST",
                  "comma-separated meshes for the BVH timing table, or none (default: cow, "
                  "maxplanck and CBlucy of the course library the first scene is in)",
                  [&o](const std::vector<std::string>& v) {
                      if (v[0] == "none")
                          o.noBvhScenes = true;
                      else
                          o.bvhScenes = splitList(v[0]);
                  });
    o.scenes = parser.parse(std::vector<std::string>(args.begin() + 1, args.end()));
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (o.scenes.empty()) throw UsageError("needs at least one scene file");
    if (o.dir.empty()) throw UsageError("needs -o DIR");
    o.commandLine = "kiln report";
    for (const std::string& a : args) {
        // The captions are commands split at spaces: a path with a space could not be one.
        if (a.find_first_of(" \t\n") != std::string::npos)
            throw UsageError("'" + a + "': kiln report cs184 takes no paths with spaces");
        o.commandLine += " " + a;
    }
    for (const std::string& m : o.bvhScenes)
        if (!fs::exists(m)) throw UsageError("--bvh-scenes: '" + m + "' does not exist");
    try {
        checkColorConfig("", o.view);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    std::error_code ec;
    fs::create_directories(o.dir, ec);
    if (ec || !fs::is_directory(o.dir))
        throw UsageError("cannot create output directory '" + o.dir + "'");
    Cs184Report(o).run();
    return 0;
}

}  // namespace kiln
