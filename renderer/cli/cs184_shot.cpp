#include "renderer/cli/cs184_shot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "renderer/cli/render_command.h"

namespace kiln::cs184 {

namespace fs = std::filesystem;

std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

namespace {

// kiln render's options parsed from a command line without its "kiln render" words.
RenderCommand parseRender(const std::vector<std::string>& args, std::vector<std::string>& scenes) {
    RenderCommand c;
    ArgParser parser("render", "");
    addRenderOptions(parser, c);
    scenes = parser.parse(args);
    return c;
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

}  // namespace

RenderJobOptions jobForFlags(const std::string& flags) {
    std::vector<std::string> scenes;
    return renderJobOptions(parseRender(words(flags), scenes));
}

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return -1;
    auto mid = v.begin() + long(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

ImageMeasures measureImage(const Film& film, int spp) {
    ImageMeasures m;
    const int w = film.width(), h = film.height();
    const double pixels = double(w) * h;
    double lum = 0, early = 0, earlyLit = 0, black = 0, earlyBlack = 0;
    uint64_t samples = 0;
    std::vector<double> relative;
    m.minSpp = UINT32_MAX;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double l = luminance(film.pixel(x, y));
            lum += l;
            if (l > 0) relative.push_back(std::sqrt(film.luminanceVariance(x, y)) / l);
            uint32_t n = film.samples(x, y);
            samples += n;
            m.minSpp = std::min(m.minSpp, n), m.maxSpp = std::max(m.maxSpp, n);
            const bool stopped = n < uint32_t(spp);
            early += stopped;
            (l > 0 ? earlyLit : earlyBlack) += stopped;
            black += l <= 0;
        }
    m.meanLuminance = lum / pixels;
    m.meanSpp = double(samples) / pixels;
    m.stoppedEarly = early / pixels;
    m.blackFraction = black / pixels;
    m.stoppedEarlyLit = pixels > black ? earlyLit / (pixels - black) : 0;
    m.stoppedEarlyBlack = black > 0 ? earlyBlack / black : 0;
    if (m.minSpp >= 2) m.noise = median(std::move(relative));
    return m;
}

double medianRelativeDifference(const Film& image, const Film& reference) {
    std::vector<double> relative;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            if (double r = luminance(reference.pixel(x, y)); r > 0)
                relative.push_back(std::abs(luminance(image.pixel(x, y)) - r) / r);
    return median(std::move(relative));
}

std::string ShotRunner::command(const std::string& flags, int width, int height,
                                const std::string& file) const {
    std::string c =
        "kiln render " + scenePath_ + " -r " + std::to_string(width) + " " + std::to_string(height);
    for (const std::string& w : words(flags)) c += " " + w;
    if (threads_ > 0) c += " -t " + std::to_string(threads_);
    return c + " --view " + view_ + " -f " + (fs::path(dir_) / file).string();
}

ShotResult ShotRunner::run(const std::string& flags, int width, int height, const std::string& file,
                           Film* keep) const {
    auto start = std::chrono::steady_clock::now();
    ShotResult r;
    r.command = command(flags, width, height, file);
    r.file = file;
    std::vector<std::string> args = words(r.command), scenes;
    args.erase(args.begin(), args.begin() + 2);  // "kiln render"
    RenderCommand c = parseRender(args, scenes);
    if (scenes.size() != 1 || scenes[0] != scenePath_)
        throw std::logic_error("report: a command names another scene: " + r.command);
    RenderJobOptions options = renderJobOptions(c);
    options.settings.progress = false;
    checkColour(c);
    OutputPaths out = outputPaths(c, scenePath_);
    std::unique_ptr<Accelerator> own;
    const bool embreeDefaults = c.accel.kind == AcceleratorKind::Embree &&
                                c.accel.embree.quality == EmbreeOptions{}.quality &&
                                c.accel.embree.robust && !c.accel.embree.watertight &&
                                !c.accel.embree.compact;
    if (!embreeDefaults) {
        auto built = std::chrono::steady_clock::now();
        own = c.accel.build(scene_, &options);
        r.buildSeconds = secondsSince(built);
    }
    const Accelerator& accel = own ? *own : embree_;
    RenderJob job(scene_, accel, options);
    Film film = job.makeFilm();
    r.stats = job.render(film);
    writePreview(out.preview, film, c.display, c.view, c.exposure);
    if (options.settings.adaptiveStep() > 0) {
        r.rateFile = fs::path(file).replace_extension(".samples.png").string();
        writeSampleHeatMap(fs::path(out.exr).replace_extension(".samples.png").string(), film);
    }
    r.accelDescription = accel.stats().description;
    r.width = width, r.height = height, r.spp = options.settings.spp;
    r.image = measureImage(film, r.spp);
    if (keep) *keep = std::move(film);
    r.wallSeconds = secondsSince(start);
    return r;
}

ImageMeasures ShotRunner::writeLayer(const Film& film, const std::string& layer,
                                     const std::string& file) const {
    Film part = layerFilm(film, layer);
    writePreview((fs::path(dir_) / file).string(), part, "", view_);
    return measureImage(part, 0);
}

}  // namespace kiln::cs184
