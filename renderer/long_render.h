// A render that survives its process: resumed from OUT.ckpt, checkpointed every N seconds and on
// request (SIGUSR1), stopped by a time limit or a signal at a pixel boundary with its checkpoint
// written, and refined to more samples. The pixels equal those of one uninterrupted render, bit for
// bit (the film's sums are exact and every sample is a pure function of seed, pixel and index).
#pragma once

#include <functional>
#include <string>

#include "renderer/checkpoint.h"

namespace kiln {

struct LongRenderOptions {
    std::string checkpointPath;  // "": no checkpoints
    double checkpointEverySeconds = 0;
    double timeLimitSeconds = 0;  // counted from start
    bool resume = false;          // continue from checkpointPath when it exists
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    Fingerprint fingerprint;
    // The EXR metadata for the film so far (kept in the checkpoint for kiln merge).
    std::function<Metadata(const RenderStats&, const Film&)> metadata;
    // Where a note or warning goes (a failed periodic checkpoint is reported and the render goes
    // on: the previous checkpoint is still valid).
    std::function<void(const std::string&)> report;
};

struct LongRenderResult {
    Film film;
    RenderStats stats;      // this run's
    CheckpointInfo totals;  // over every run, as the final checkpoint holds them
    bool resumed = false;
    double checkpointSeconds = 0;  // the final checkpoint's write
    uint64_t checkpointBytes = 0;
};

// Bytes a render of these options needs: the film in memory, the outputs on disk (the EXR as
// uncompressed float, an upper bound; the checkpoint when written) and the EXR write's memory.
struct OutputSizes {
    uint64_t film = 0, exr = 0, preview = 0, checkpoint = 0, writeMemory = 0;
};
OutputSizes estimateOutputs(const RenderJobOptions& options, bool checkpoint);

// Throws CheckpointError when the checkpoint to resume is damaged or belongs to another render
// (bad input), std::runtime_error when the final checkpoint cannot be written.
// = renderLongFilm, then writeFinalCheckpoint.
LongRenderResult runLongRender(const RenderJob& job, const LongRenderOptions& options);

// The render alone: resumed, checkpointed periodically, stopped by the time limit or a signal; the
// final checkpoint is not written yet (kiln render writes the images first, so a checkpoint that
// does not fit the disk cannot cost the finished image).
LongRenderResult renderLongFilm(const RenderJob& job, const LongRenderOptions& options);

// Writes the final checkpoint of result (when options name one) and records its size and time.
// Throws std::runtime_error when it cannot be written (the previous checkpoint stays).
void writeFinalCheckpoint(const LongRenderOptions& options, LongRenderResult& result);

// A resume's checks that need no scene, before it is loaded: the checkpoint's header (when there
// is one) against the fields of fingerprintBeforeLoad, and its region and samples against
// settings. A refused resume then costs no load, build or probe (ground rule: exit 2 before
// expensive work); resumeFilm checks the whole fingerprint after. Throws CheckpointError.
void checkResumeBeforeLoad(const std::string& checkpointPath, const RenderSettings& settings,
                           const Fingerprint& beforeLoad);

// The film a resume starts from, checked against the job; nullopt-like empty film (0 x 0) when
// there is no checkpoint. Throws CheckpointError naming what differs.
Film resumeFilm(const RenderJob& job, const LongRenderOptions& options, CheckpointInfo& previous);

}  // namespace kiln
