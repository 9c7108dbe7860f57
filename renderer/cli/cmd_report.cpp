// kiln report cs184: the five parts of the CS184 PathTracer write-up (ray generation and
// intersection, direct lighting, global illumination, Russian roulette, adaptive sampling) for the
// given scenes, every image rendered through RenderJob and captioned with the kiln flags that
// make it, sized to a time budget, as one HTML page.
#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "color/image_output.h"
#include "renderer/accel/brute_force.h"
#include "renderer/cli/accel_options.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/html_page.h"
#include "renderer/cli/render_options.h"
#include "renderer/core/log.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

struct ReportOptions {
    std::vector<std::string> scenes;
    std::string dir;
    double budget = 300;  // seconds for the whole report
    int threads = 0;
    std::string view = "CS184";
};

// One image of the page: the kiln render flags that make it (without -r and -t).
struct Shot {
    std::string id, caption, flags;
    int sppDivisor = 1;  // the budget's reduction of -s
};

// A figure: a row of shots with a heading and a sentence saying what to look at.
struct Figure {
    int part;
    std::string title, note;
    std::vector<Shot> shots;
};

std::vector<Figure> cs184Figures() {
    std::vector<Figure> f;
    f.push_back({1,
                 "Normal shading",
                 "Part 1: camera rays and intersection.",
                 {{"normals", "normal shading", "-i normals -s 1"}}});
    f.push_back(
        {2,
         "Uniform hemisphere against light importance sampling",
         "Part 2, direct lighting only (-m 1), the same rays per pixel: hemisphere sampling "
         "is noisier and cannot see point lights.",
         {{"hemisphere", "uniform hemisphere (-H)", "-m 1 -H -s 16 -l 8"},
          {"importance", "light importance sampling", "-m 1 --sampling light -s 16 -l 8"}}});
    Figure lightRays{2, "Light rays per shading point", "Part 2: 1 camera ray per pixel.", {}};
    for (int l : {1, 4, 16, 64})
        lightRays.shots.push_back({"l" + std::to_string(l), "-l " + std::to_string(l),
                                   "-m 1 --sampling light -s 1 -l " + std::to_string(l)});
    f.push_back(lightRays);
    f.push_back({3,
                 "Direct and indirect illumination",
                 "Part 3: one global illumination render and its two halves (kiln's direct and "
                 "indirect AOVs).",
                 {{"gi", "global illumination", "-s 64 -l 4 -m 5 --aov direct,indirect"},
                  {"gi.direct", "direct only", "-s 64 -l 4 -m 5 --aov direct,indirect"},
                  {"gi.indirect", "indirect only", "-s 64 -l 4 -m 5 --aov direct,indirect"}}});
    Figure depth{3, "Maximum ray depth, bounces accumulated", "Part 3: -m 0 is emission only.", {}};
    Figure bounce{3, "The m-th bounce only (-o 0)", "Part 3: accumulation off.", {}};
    for (int m : {0, 1, 2, 3, 4, 5, 100}) {
        std::string ms = std::to_string(m);
        depth.shots.push_back({"m" + ms, "-m " + ms, "-s 16 -l 4 -m " + ms});
        if (m <= 5)
            bounce.shots.push_back({"m" + ms + "o0", "bounce " + ms, "-s 16 -l 4 -o 0 -m " + ms});
    }
    f.push_back(depth);
    f.push_back(bounce);
    Figure spp{3, "Samples per pixel", "Part 3: -l 4 -m 5.", {}};
    for (int s : {1, 4, 16, 64, 256, 1024})
        spp.shots.push_back({"s" + std::to_string(s), "-s " + std::to_string(s),
                             "-l 4 -m 5 -s " + std::to_string(s)});
    f.push_back(spp);
    f.push_back({4,
                 "Russian roulette",
                 "Part 4: CS184's fixed continuation probability against kiln's throughput "
                 "roulette, both at -m 100; the table below gives their rays and times.",
                 {{"rrfixed", "--rr fixed (continue with 0.65)", "-s 64 -l 4 -m 100 --rr fixed"},
                  {"rrthroughput", "--rr throughput", "-s 64 -l 4 -m 100 --rr throughput"}}});
    f.push_back({5,
                 "Adaptive sampling",
                 "Part 5: stop a pixel when 1.96 sigma / sqrt(n) <= 0.05 mu, tested every 64 "
                 "samples; the rate image runs from blue (few samples) to red (many).",
                 {{"adaptive", "adaptive sampling", "-s 1024 -a 64 0.05 -l 1 -m 5"}}});
    return f;
}

std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

// The job kiln render would run for these flags at this size: parsed by kiln render's own options.
RenderJobOptions jobFor(const std::string& flags, int width, int height, int threads) {
    ArgParser parser("render", "");
    RenderJobArgs args;
    std::string unusedOutput;
    args.addOptions(parser);
    addOutputNameOptions(parser, unusedOutput, args.job.path);
    parser.parse(words(flags));
    RenderJobOptions o = args.finish();
    o.settings.width = width, o.settings.height = height;
    o.settings.threads = threads;
    o.settings.progress = false;
    return o;
}

std::string sppFlags(const Shot& shot) {
    if (shot.sppDivisor == 1) return shot.flags;
    std::vector<std::string> w = words(shot.flags);
    std::string out;
    for (size_t i = 0; i < w.size(); ++i) {
        if (w[i] == "-s" && i + 1 < w.size())
            w[i + 1] = std::to_string(std::max(1, std::stoi(w[i + 1]) / shot.sppDivisor));
        out += (i ? " " : "") + w[i];
    }
    return out;
}

// Work of a render in units of one ray-vertex: camera ray, then per vertex the light samples and
// the next bounce (roulette ends long paths; -m 100 counts as 6 vertices).
double workUnits(const RenderJobOptions& o) {
    double vertices = o.integrator == IntegratorKind::Normals ? 0 : std::min(o.path.maxDepth, 6);
    return double(o.settings.width) * o.settings.height * o.settings.spp *
           (1 + vertices * (std::max(1, o.path.lightSamples) + 1));
}

struct Size {
    int width, height;
};
// The report's image sizes, largest first (the course's 4:3).
constexpr Size kSizes[] = {{640, 480}, {480, 360}, {320, 240}, {240, 180},
                           {160, 120}, {120, 90},  {80, 60}};

// The largest 4:3 size, then the smallest -s divisor, whose estimated time fits the share.
Size fitBudget(std::vector<Figure>& figures, double secondsPerUnit, double share, int threads,
               int& divisor) {
    auto estimate = [&](Size s, int div) {
        double total = 0;
        for (Figure& f : figures)
            for (Shot& shot : f.shots) {
                shot.sppDivisor = div;
                total +=
                    workUnits(jobFor(sppFlags(shot), s.width, s.height, threads)) * secondsPerUnit +
                    0.05;  // loading the preview's colour transform, writing the PNG
            }
        return total;
    };
    divisor = 1;
    for (Size s : kSizes)
        if (estimate(s, 1) <= share) return s;
    Size smallest = kSizes[std::size(kSizes) - 1];
    while (divisor < 1024 && estimate(smallest, divisor) > share) divisor *= 2;
    estimate(smallest, divisor);
    return smallest;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A film holding one colour AOV layer ("direct", "indirect") of a render, to display on its own.
Film layerFilm(const Film& film, const std::string& layer) {
    Film out(film.width(), film.height());
    out.setScaleExponent(film.scaleExponent());
    const auto& channels = film.layout().channels();
    size_t first = channels.size();
    for (size_t c = 0; c < channels.size(); ++c)
        if (channels[c].name == layer + ".R") first = c;
    if (first + 2 >= channels.size()) throw std::logic_error("report: no AOV layer " + layer);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            out.add(
                x, y,
                Color(film.aov(x, y, first), film.aov(x, y, first + 1), film.aov(x, y, first + 2)));
    return out;
}

// The prefix of a scene's image files: its name in safe characters, numbered from the second scene
// on, so two scenes of one name (or a name with '#' or '?') cannot clash or break a link.
std::string imageStem(const std::string& scenePath, size_t index) {
    std::string stem = fs::path(scenePath).stem().string();
    for (char& c : stem)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    return index == 0 ? stem : stem + "_" + std::to_string(index + 1);
}

struct SceneReport {
    std::string path, stem;
    Scene scene;
    std::unique_ptr<Accelerator> embree;
};

class Cs184Report {
  public:
    Cs184Report(const ReportOptions& o) : o_(o), page_("kiln: CS184 PathTracer report") {}
    void run();

  private:
    RenderStats render(SceneReport& s, const Accelerator& accel, const RenderJobOptions& job,
                       const std::string& file, Film* keep = nullptr);
    void timingTable(SceneReport& s, Size size, double share);
    // The figures; once the scene's time is spent (the machine got slower than the probe said),
    // the rest are rendered with -s divided by 16 more and say so.
    void figures(SceneReport& s, std::vector<Figure>& figs, Size size,
                 std::chrono::steady_clock::time_point deadline);

    const ReportOptions& o_;
    HtmlPage page_;
    std::vector<std::vector<std::string>> rouletteRows_;
};

RenderStats Cs184Report::render(SceneReport& s, const Accelerator& accel,
                                const RenderJobOptions& job, const std::string& file, Film* keep) {
    RenderJob rj(s.scene, accel, job);
    Film film = rj.makeFilm();
    RenderStats stats = rj.render(film);
    if (!file.empty()) writePreview((fs::path(o_.dir) / file).string(), film, "sRGB", o_.view);
    if (keep) *keep = std::move(film);
    return stats;
}

std::string fixed(double v, int digits) { return fmt::format("{:.{}f}", v, digits); }

std::string significant(double v) { return fmt::format("{:.3g}", v); }

// Part 1's table: normal shading with Embree, the reference BVH and no BVH at all.
void Cs184Report::timingTable(SceneReport& s, Size size, double share) {
    // The size of the figures, or a smaller one where brute force fits a twentieth of the share.
    auto normalsAt = [&](Size z) {
        return jobFor("-i normals -s 1", z.width, z.height, o_.threads);
    };
    Size at = size;
    bool bruteFits = false;
    for (Size z : kSizes)
        if (z.width <= size.width && bruteForceSeconds(s.scene, normalsAt(z)) <= 0.05 * share) {
            at = z, bruteFits = true;
            break;
        }
    RenderJobOptions job = normalsAt(at);
    std::vector<std::vector<std::string>> rows;
    auto row = [&](const std::string& name, const Accelerator& accel) {
        RenderStats st = render(s, accel, job, "");
        rows.push_back({name, accel.stats().description, fixed(accel.stats().buildSeconds, 4),
                        fixed(st.seconds, 4), significant(double(st.rays) / st.seconds * 1e-6)});
    };
    row("Embree", *s.embree);
    auto bvh = makeReferenceAccelerator(s.scene, {BvhSplit::MeanCentroid, 4});
    row("reference BVH (CS184's split)", *bvh);
    if (bruteFits)
        row("no BVH (--accel brute)", *makeBruteForceAccelerator(s.scene));
    else
        rows.push_back({"no BVH (--accel brute)", "not run: over a twentieth of the budget", "-",
                        "about " + fixed(bruteForceSeconds(s.scene, job), 1), "-"});
    page_.paragraph("Render time with and without a BVH, normal shading at " +
                    std::to_string(at.width) + "x" + std::to_string(at.height) + ", 1 spp (" +
                    std::to_string(bruteForcePrimitiveCount(s.scene)) + " primitives):");
    page_.table({"traversal", "structure", "build s", "render s", "Mrays/s"}, rows);
}

void Cs184Report::figures(SceneReport& s, std::vector<Figure>& figs, Size size,
                          std::chrono::steady_clock::time_point deadline) {
    int part = 1;  // the timing table opened part 1
    const char* parts[] = {"",
                           "Part 1: ray generation and intersection",
                           "Part 2: direct lighting",
                           "Part 3: global illumination",
                           "Part 4: Russian roulette",
                           "Part 5: adaptive sampling"};
    std::vector<std::vector<std::string>> rrRows;
    for (Figure& f : figs) {
        if (f.part != part) page_.heading(3, parts[part = f.part]);
        page_.heading(4, f.title);
        page_.paragraph(f.note);
        std::vector<HtmlPage::Image> row;
        Film kept(1, 1);
        std::string keptFlags;
        for (Shot shot : f.shots) {
            bool late = std::chrono::steady_clock::now() > deadline;
            if (late) shot.sppDivisor *= 16;
            std::string flags = sppFlags(shot), file = s.stem + "_" + shot.id + ".png";
            std::string dims =
                "-r " + std::to_string(size.width) + " " + std::to_string(size.height);
            std::string command =
                "kiln render " + fs::path(s.path).filename().string() + " " + dims + " " + flags;
            size_t dot = shot.id.find('.');
            if (dot != std::string::npos && flags == keptFlags) {
                // A layer of the render before it.
                writePreview((fs::path(o_.dir) / file).string(),
                             layerFilm(kept, shot.id.substr(dot + 1)), "sRGB", o_.view);
                row.push_back(
                    {file, shot.caption,
                     command + " (the " + shot.id.substr(dot + 1) + " layer of its EXR)"});
                continue;
            }
            RenderJobOptions job = jobFor(flags, size.width, size.height, o_.threads);
            RenderStats st = render(s, *s.embree, job, file, &kept);
            keptFlags = flags;
            std::string timing =
                fixed(st.seconds, 2) + " s, " + fixed(double(st.rays) / 1e6, 2) + " Mrays";
            row.push_back(
                {file, shot.caption + " (" + timing + (late ? "; -s cut: over budget" : "") + ")",
                 command});
            if (f.part == 4)
                rrRows.push_back({shot.caption, std::to_string(st.rays),
                                  fixed(double(st.rays) / double(st.samples), 2),
                                  fixed(st.seconds, 3)});
            if (job.settings.adaptiveBatch > 0) {
                std::string rate = s.stem + "_" + shot.id + "_rate.png";
                writeSampleHeatMap((fs::path(o_.dir) / rate).string(), kept);
                row.push_back(
                    {rate,
                     "sample rate: " + fixed(double(st.samples) / (size.width * size.height), 1) +
                         " samples per pixel on average, of at most " +
                         std::to_string(job.settings.spp),
                     command + " (OUT.samples.png)"});
            }
        }
        page_.images(row);
        if (f.part == 4 && !rrRows.empty()) {
            page_.table({"roulette", "rays", "rays per camera sample", "render s"}, rrRows);
            rrRows.clear();
        }
    }
}

void Cs184Report::run() {
    auto start = std::chrono::steady_clock::now();
    // Every scene loaded first: a bad file is refused before any rendering.
    std::vector<SceneReport> scenes;
    for (const std::string& path : o_.scenes) {
        SceneReport s;
        s.path = path;
        s.stem = imageStem(path, scenes.size());
        s.scene = loadScene(path);
        scenes.push_back(std::move(s));
    }
    for (SceneReport& s : scenes) s.embree = makeEmbreeAccelerator(s.scene);
    double share = std::max(1.0, (o_.budget - secondsSince(start)) / double(scenes.size()));
    page_.paragraph("Made by: kiln report cs184 " +
                    [&] {
                        std::string all;
                        for (const auto& s : o_.scenes) all += s + " ";
                        return all;
                    }() +
                    "--budget " + fixed(o_.budget, 0) +
                    ". Images are displayed with the OCIO view '" + o_.view + "'" +
                    (o_.view == "CS184" ? " (the course's sqrt(2) exposure, gamma 2.2)" : "") +
                    "; each caption gives the kiln render flags that make it.");
    for (SceneReport& s : scenes) {
        auto sceneStart = std::chrono::steady_clock::now();
        // Time per unit of work, from a small global illumination render of this scene.
        RenderJobOptions probe = jobFor("-s 2 -l 4 -m 5", 80, 60, o_.threads);
        RenderStats p = render(s, *s.embree, probe, "");
        double perUnit = std::max(p.seconds, 1e-4) / workUnits(probe);
        std::vector<Figure> figs = cs184Figures();
        int divisor = 1;
        Size size = fitBudget(figs, perUnit, 0.7 * share, o_.threads, divisor);
        page_.heading(2, s.stem + " (" + s.path + ")");
        page_.paragraph(std::to_string(size.width) + "x" + std::to_string(size.height) +
                        (divisor > 1 ? ", every -s divided by " + std::to_string(divisor) : "") +
                        " to fit this scene's share of the budget, " + fixed(share, 0) + " s.");
        page_.heading(3, "Part 1: ray generation and intersection");
        timingTable(s, size, share);
        figures(s, figs, size,
                sceneStart + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(0.9 * share)));
        page_.paragraph("Scene time: " + fixed(secondsSince(sceneStart), 1) + " s.");
        logInfo("report: {} done, {:.1f} s", s.path, secondsSince(sceneStart));
    }
    page_.paragraph("Total time: " + fixed(secondsSince(start), 1) + " s of a " +
                    fixed(o_.budget, 0) + " s budget.");
    std::string index = (fs::path(o_.dir) / "index.html").string();
    page_.write(index);
    logInfo("report: {}, {:.1f} s", index, secondsSince(start));
}

}  // namespace

int runReport(const std::vector<std::string>& args) {
    if (args.empty() || args[0] != "cs184")
        throw UsageError("usage: kiln report cs184 SCENE... -o DIR [--budget SECONDS]");
    ReportOptions o;
    ArgParser parser("report cs184",
                     "SCENE... -o DIR [--budget SECONDS] [-t N] [--view NAME]   (DIR/index.html)");
    parser.option("output", "o", 1, "DIR", "directory for index.html and its images (created)",
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
    o.scenes = parser.parse(std::vector<std::string>(args.begin() + 1, args.end()));
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (o.scenes.empty()) throw UsageError("needs at least one scene file");
    if (o.dir.empty()) throw UsageError("needs -o DIR");
    try {
        checkColorConfig("sRGB", o.view);
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
