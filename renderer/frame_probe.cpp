#include "renderer/frame_probe.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace kiln {

FrameProbe probeFrame(const RenderJob& job, int maxPixels, int spp) {
    const RenderSettings& s = job.options().settings;
    const int w = s.filmWidth(), h = s.filmHeight();
    FrameProbe probe;
    if (w <= 0 || h <= 0 || maxPixels <= 0 || spp <= 0) return probe;
    // At most a quarter of the render's own camera samples: a thumbnail's probe (a batch
    // turntable's 64x48 frames at 1 sample) traced twice the render's samples.
    const int64_t renderSamples = int64_t(w) * h * std::max(1, s.spp - s.sampleStart);
    maxPixels = int(std::clamp<int64_t>(renderSamples / (4 * int64_t(spp)), 1, maxPixels));
    // An nx x ny grid of the region's aspect, at most maxPixels, never more than the region has.
    double scale = std::sqrt(double(maxPixels) / (double(w) * double(h)));
    int nx = std::clamp(int(w * scale), 1, w), ny = std::clamp(int(h * scale), 1, h);
    probe.pixels = nx * ny;
    probe.samplesPerPixel = spp;
    std::vector<double> sums(size_t(probe.pixels), 0.0);
    std::vector<int> finite(size_t(probe.pixels), 0);
    // Probe pixels [begin, end), their samples traced as one batch (a pixel's samples alone
    // made batches of two: packets of 16 rays with 14 empty lanes).
    auto trace = [&](int begin, int end) {
        std::vector<PixelXY> pixels;
        for (int i = begin; i < end; ++i)
            pixels.push_back({s.filmOriginX() + int((i % nx + 0.5) * w / nx),
                              s.filmOriginY() + int((i / nx + 0.5) * h / ny)});
        RayCounter counter;
        const std::vector<SampleRecord> records =
            job.traceSamples(pixels, s.sampleStart, spp, counter);
        for (size_t k = 0; k < records.size(); ++k) {
            const size_t i = size_t(begin) + k / size_t(spp);
            double y = luminance(records[k].L);
            if (std::isfinite(y)) sums[i] += y, ++finite[i];
        }
    };
    constexpr int kPixelsPerBatch = 64;
    tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, (probe.pixels + kPixelsPerBatch - 1) / kPixelsPerBatch, [&](int b) {
            trace(b * kPixelsPerBatch, std::min(probe.pixels, (b + 1) * kPixelsPerBatch));
        });
    });
    double total = 0;
    int count = 0;
    for (int i = 0; i < probe.pixels; ++i) {
        total += sums[size_t(i)], count += finite[size_t(i)];
        if (finite[size_t(i)])
            probe.maxPixelLuminance =
                std::max(probe.maxPixelLuminance, sums[size_t(i)] / finite[size_t(i)]);
    }
    probe.meanLuminance = count ? total / count : 0.0;
    return probe;
}

std::optional<std::string> blackImageWarning(const FrameProbe& probe, float exposureStops) {
    if (probe.pixels == 0) return std::nullopt;
    double gain = std::exp2(double(exposureStops));
    double mean = probe.meanLuminance * gain, brightest = probe.maxPixelLuminance * gain;
    if (!(mean < kBlackMeanLuminance)) return std::nullopt;
    return fmt::format(
        "the image will look black: a probe of {} pixels x {} samples across the frame finds a "
        "mean luminance of {:.3g} (brightest pixel {:.3g}; under {:g} shows as black). The "
        "lights may be too dim or too far for the scene's size, or the camera sees nothing lit",
        probe.pixels, probe.samplesPerPixel, mean, brightest, kBlackMeanLuminance);
}

}  // namespace kiln
