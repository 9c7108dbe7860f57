#include "renderer/long_render.h"

#include <algorithm>
#include <filesystem>

namespace kiln {
namespace {

// The checkpoint at path against a render of these settings and this fingerprint (whole, or the
// fields fingerprintBeforeLoad has: the saved one's other fields are then not compared).
void checkResumable(const CheckpointInfo& saved, const std::string& path, const RenderSettings& s,
                    const Fingerprint& fingerprint, bool whole) {
    std::string name = std::filesystem::path(path).filename().string();
    Fingerprint compared;
    for (const auto& field : saved.fingerprint)
        if (whole || std::any_of(fingerprint.begin(), fingerprint.end(),
                                 [&](const auto& f) { return f.first == field.first; }))
            compared.push_back(field);
    std::string diff = fingerprintDifference(compared, fingerprint, name);
    if (!diff.empty()) throw CheckpointError(path + ": belongs to another render: " + diff);
    CheckpointInfo here;
    here.fullWidth = s.width, here.fullHeight = s.height;
    here.originX = s.filmOriginX(), here.originY = s.filmOriginY();
    here.width = s.filmWidth(), here.height = s.filmHeight();
    if (saved.regionText() != here.regionText())
        throw CheckpointError(path + ": holds region " + saved.regionText() + ", this render " +
                              here.regionText() + " (--crop differs)");
    if (saved.sampleStart != s.sampleStart)
        throw CheckpointError(path + ": holds samples from " + std::to_string(saved.sampleStart) +
                              ", this render starts at " + std::to_string(s.sampleStart) +
                              " (--sample-range differs)");
    if (saved.sampleEnd > s.spp)
        throw CheckpointError(path + ": holds samples up to " + std::to_string(saved.sampleEnd) +
                              ", more than this render's " + std::to_string(s.spp) +
                              " (-s or --sample-range must not shrink)");
}

CheckpointInfo totalsOf(const LongRenderOptions& options, const RenderJob& job, const Film& film,
                        const RenderStats& run, const CheckpointInfo& previous) {
    RenderStats all = run;
    all.rays += previous.rays;
    all.nonFiniteSamples += previous.nonFiniteSamples;
    all.seconds += previous.seconds;
    Metadata meta = options.metadata ? options.metadata(all, film) : Metadata{};
    return checkpointInfo(options.fingerprint, job.options(), film, all, meta);
}

}  // namespace

OutputSizes estimateOutputs(const RenderJobOptions& options, bool checkpoint) {
    const RenderSettings& s = options.settings;
    uint64_t pixels = uint64_t(s.filmWidth()) * uint64_t(s.filmHeight()), perPixel = 0;
    Film one(1, 1, options.aovs);
    for (const FilmBuffer& b : one.buffers()) perPixel += b.bytes(1);
    uint64_t exrChannels = 4 + one.layout().channels().size() + options.aovs.has(AovKind::Samples) +
                           options.aovs.has(AovKind::Variance);
    OutputSizes out;
    out.film = pixels * perPixel;
    out.exr = pixels * exrChannels * 4 + (1 << 16);
    out.preview = pixels * 4 + (1 << 16);
    out.checkpoint = checkpoint ? out.film + (1 << 16) : 0;
    // The float ImageBuf the EXR is assembled in, and OpenEXR's line buffers beside it.
    out.writeMemory = out.exr + out.exr / 4;
    return out;
}

Film resumeFilm(const RenderJob& job, const LongRenderOptions& options, CheckpointInfo& previous) {
    const std::string& path = options.checkpointPath;
    if (!options.resume || path.empty() || !std::filesystem::exists(path)) return Film(0, 0);
    previous = readCheckpointInfo(path);
    checkResumable(previous, path, job.options().settings, options.fingerprint, true);
    return readCheckpoint(path, previous);
}

void checkResumeBeforeLoad(const std::string& checkpointPath, const RenderSettings& settings,
                           const Fingerprint& beforeLoad) {
    if (std::filesystem::exists(checkpointPath))
        checkResumable(readCheckpointInfo(checkpointPath), checkpointPath, settings, beforeLoad,
                       false);
}

LongRenderResult renderLongFilm(const RenderJob& job, const LongRenderOptions& options) {
    LongRenderResult result{Film(0, 0), {}, {}, false};
    CheckpointInfo previous;
    result.film = resumeFilm(job, options, previous);
    result.resumed = result.film.width() > 0;
    if (!result.resumed) result.film = job.makeFilm();
    if (options.report && result.resumed)
        options.report("resuming " + options.checkpointPath + ": " +
                       std::to_string(result.film.totalSamples()) + " samples done");

    RenderControl control;
    control.start = options.start;
    control.timeLimitSeconds = options.timeLimitSeconds;
    control.checkpointEverySeconds =
        options.checkpointPath.empty() ? 0 : options.checkpointEverySeconds;
    if (!options.checkpointPath.empty())
        control.checkpoint = [&](const Film& film, const RenderStats& run) {
            try {
                writeCheckpoint(options.checkpointPath, totalsOf(options, job, film, run, previous),
                                film);
            } catch (const std::exception& e) {
                if (options.report)
                    options.report(std::string("warning: checkpoint not written (the previous one "
                                               "stays valid): ") +
                                   e.what());
            }
        };
    result.stats = job.render(result.film, control);
    result.totals = totalsOf(options, job, result.film, result.stats, previous);
    return result;
}

void writeFinalCheckpoint(const LongRenderOptions& options, LongRenderResult& result) {
    if (options.checkpointPath.empty()) return;
    auto t0 = std::chrono::steady_clock::now();
    writeCheckpoint(options.checkpointPath, result.totals, result.film);
    result.checkpointSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.checkpointBytes = std::filesystem::file_size(options.checkpointPath);
}

LongRenderResult runLongRender(const RenderJob& job, const LongRenderOptions& options) {
    LongRenderResult result = renderLongFilm(job, options);
    writeFinalCheckpoint(options, result);
    return result;
}

}  // namespace kiln
