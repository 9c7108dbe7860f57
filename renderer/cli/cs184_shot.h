// One image of kiln report cs184: its caption's command ("kiln render SCENE -r W H FLAGS ... -f
// FILE.png") parsed by kiln render's own parser and run as kiln render runs it, on the scene loaded
// once, so the caption is the command run. What the image measured comes back with it: time, rays,
// samples, noise, and for adaptive sampling the per-pixel sample counts.
#pragma once

#include <string>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "renderer/film/film.h"
#include "renderer/render_job.h"

namespace kiln::cs184 {

std::vector<std::string> words(const std::string& text);

// The job kiln render would run for these flags (besides the scene): the planner's cost model
// reads it. Throws UsageError.
RenderJobOptions jobForFlags(const std::string& flags);

// What an image shows, measured on its film.
struct ImageMeasures {
    double meanLuminance = 0;
    // The median over the lit pixels of the standard error of the pixel's luminance mean (from
    // its own samples) over that mean: a typical pixel's relative noise, which the few pixels
    // on an emitter's edge cannot dominate. -1 where a pixel has fewer than two samples.
    double noise = -1;
    double meanSpp = 0;
    uint32_t minSpp = 0, maxSpp = 0;
    double stoppedEarly = 0;  // fraction of pixels with fewer samples than -s (adaptive)
    // The same among the lit pixels, and among the black ones (all samples zero: their interval
    // is zero at the first check).
    double stoppedEarlyLit = 0, stoppedEarlyBlack = 0;
    double blackFraction = 0;
};
ImageMeasures measureImage(const Film& film, int spp);
// The median over the lit pixels of |image - reference| / reference in luminance: the noise of
// a 1-sample image against a many-sample one of the same estimate (whose own noise counts too).
double medianRelativeDifference(const Film& image, const Film& reference);

struct ShotResult {
    std::string command;         // exactly what was parsed and run
    std::string file, rateFile;  // relative to the page; rateFile only with -a
    RenderStats stats;
    double wallSeconds = 0;  // the whole command: job set-up, render, PNG writes
    std::string accelDescription;
    double buildSeconds = 0;  // the accelerator's, where this command built one
    int width = 0, height = 0, spp = 0;
    ImageMeasures image;
};

class ShotRunner {
  public:
    // scenePath and dir as the user gave them (the commands name them so); embree is the
    // scene's Embree accelerator, used by every command that asks for Embree's defaults.
    ShotRunner(const Scene& scene, const Accelerator& embree, std::string scenePath,
               std::string dir, int threads, std::string view)
        : scene_(scene),
          embree_(embree),
          scenePath_(std::move(scenePath)),
          dir_(std::move(dir)),
          threads_(threads),
          view_(std::move(view)) {}

    // "kiln render SCENE -r W H FLAGS [-t N] --view V -f DIR/FILE.png"
    std::string command(const std::string& flags, int width, int height,
                        const std::string& file) const;
    // Runs the command; keep (if given) receives the film.
    ShotResult run(const std::string& flags, int width, int height, const std::string& file,
                   Film* keep = nullptr) const;
    // A colour layer ("direct") of a kept film written as its own image, as the layer of the
    // EXR the command writes would show.
    ImageMeasures writeLayer(const Film& film, const std::string& layer,
                             const std::string& file) const;

  private:
    const Scene& scene_;
    const Accelerator& embree_;
    std::string scenePath_, dir_;
    int threads_;
    std::string view_;
};

}  // namespace kiln::cs184
