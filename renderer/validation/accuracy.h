// Error-versus-time measurement: image error statistics against a reference, the log-log slope fit,
// and the efficiency figure of merit of the rendering literature, 1 / (relMSE x time).
#pragma once

#include <string>
#include <vector>

#include "color/image_input.h"
#include "renderer/film/film.h"
#include "renderer/validation/svg_plot.h"

namespace kiln {

// A beauty image (luminance is what the statistics use) with optional per-pixel variance of its
// mean.
struct Image {
    int width = 0, height = 0;
    std::vector<Color> pixels;
    std::vector<double>
        variance;  // estimator variance of each pixel's luminance mean; empty if unknown
    // Colour AOV layers ("direct", "indirect", ...), pixel for pixel.
    std::vector<std::string> layerNames;
    std::vector<std::vector<Color>> layers;
    static Image fromFilm(const Film& film);
    // From an image file's channels: beauty R, G, B (by name, else the first three), the
    // "variance" channel when present, and these colour layers (LAYER.R/G/B) when present.
    static Image fromChannels(const ChannelImage& file,
                              const std::vector<std::string>& layers = {});
    const std::vector<Color>* layer(const std::string& name) const;
};

struct ErrorStats {
    double rmse = 0;    // root mean squared error of luminance
    double relMse = 0;  // mean of (x - r)^2 / (r^2 + 0.01): relative, robust near black
    double bias = 0;    // mean(x) - mean(r): what more samples cannot remove (truncated depth)
    double referenceMean = 0;  // mean luminance of the reference, to state the bias as a fraction
};

// Error of `test` against `reference`. The reference's own variance (when known) is subtracted from
// the squared errors, so a finite-sample reference does not set a floor under the measured error.
ErrorStats compareImages(const Image& test, const Image& reference);
// The same statistics for one colour AOV layer present in both (no reference variance is known for
// AOVs).
ErrorStats compareLayer(const Image& test, const Image& reference, const std::string& layer);

// How sharp the test image keeps the reference's albedo edges (texture and geometry edges; issue
// 29): over horizontally and vertically neighbouring pixels whose albedo luminance differs by more
// than kAlbedoEdge, the test image's luminance step taken along the sign of the reference's step,
// summed, over the sum of the reference's |step|. 1: as sharp as the reference; below 1: blurred.
// Zero-mean noise leaves it unbiased (a raw render reads 1 up to its noise). Negative when the
// albedo has no such edge.
constexpr double kAlbedoEdge = 0.1;
double albedoEdgeContrast(const Image& test, const Image& reference,
                          const std::vector<Color>& albedo);

// Least-squares slope of log(y) against log(x) (e.g. relMSE against spp: -1 for an unbiased
// estimator).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);

inline double efficiency(double relMse, double seconds) {
    return relMse > 0 && seconds > 0 ? 1.0 / (relMse * seconds) : 0.0;
}

}  // namespace kiln

namespace kiln {

// One measured setting of `kiln bench accuracy`.
struct AccuracyRun {
    std::string group;  // spp, sampler, guiding, strategy, light_samples, depth, adaptive, accel
    std::string label;  // e.g. "mis", "m=3 rr", "tol=0.05"
    int spp = 0, lightSamples = 1, maxDepth = 100;
    std::string sampling = "mis", roulette = "throughput", accel = "embree", sampler;
    bool guided = false;  // diffuse bounces followed the caustic guide
    float adaptiveTolerance = 0;
    double seconds = 0, meanSpp = 0;
    uint64_t rays = 0;
    ErrorStats error;
    std::vector<std::pair<std::string, ErrorStats>> aovErrors;  // on request (--aov)
    double edgeContrast =
        -1;  // albedoEdgeContrast where the reference has albedo; < 0: not measured
    double efficiency = 0;
};

struct AccuracyOptions {
    std::string scene, outDir = "accuracy";
    int width = 128, height = 96;
    int maxSpp = 1024, referenceSpp = 4096;
    double budgetSeconds = 300;
    bool quick = false;  // a handful of settings (CI smoke run)
    std::string aovs;    // colour AOV layers whose error is measured too, e.g. "direct,indirect"
    // The spp sweep raw and denoised (group "denoised": render + denoise time, docs/denoise.md)
    // and nothing else.
    bool denoise = false;
    std::string environmentMap;  // --env: a lat-long environment light added to the scene
};

struct AccuracyResult {
    std::vector<AccuracyRun> runs;
    std::vector<std::string> skipped;
    double referenceSeconds = 0;
    bool referenceCached = false;
    bool caustics = false;  // from the render plan: explains a shallow slope
};

// Renders (or reuses, cached by scene + settings) the references, sweeps the settings within the
// budget, and writes OUT/accuracy.csv, OUT/error_vs_time.svg, OUT/spp.svg and OUT/summary.md.
// (Defined in accuracy_run.cpp.)
AccuracyResult runAccuracy(const AccuracyOptions& options);
// The CSV, SVGs and summary of a result (accuracy_report.cpp).
void writeAccuracyReport(const AccuracyOptions& options, const AccuracyResult& result);

}  // namespace kiln
