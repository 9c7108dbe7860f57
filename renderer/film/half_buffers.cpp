#include "renderer/film/half_buffers.h"

#include <algorithm>
#include <cmath>

namespace kiln {
namespace {

// Far beyond any scene, well inside the fixed-point range (fixed_sum.h).
constexpr double kMaxFeatureDepth = 1e12;

double finiteOrZero(double v) { return std::isfinite(v) ? v : 0.0; }

constexpr const char* kColourChannels[kLayerHalfChannels] = {"R",     "G",     "B",
                                                             "var_R", "var_G", "var_B"};
constexpr const char* kHalfNames[2] = {"halfA", "halfB"};

std::vector<std::string> channelsOf(const std::string& layer) {
    std::vector<std::string> names;
    for (const char* c : kColourChannels) names.push_back(layer + "." + c);
    for (const char* c : {"albedo_R", "albedo_G", "albedo_B", "N_X", "N_Y", "N_Z", "Z", "n"})
        names.push_back(layer + "." + c);
    return names;
}

}  // namespace

void halfFeatures(const SampleRecord& r, double out[kHalfFeatures]) {
    if (!r.hit) {
        std::fill_n(out, kHalfFeatures, 0.0);
        return;
    }
    const Vec3 v[2] = {r.albedo, r.normal};
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c) out[3 * k + c] = finiteOrZero(v[k][c]);
    out[6] = std::clamp(finiteOrZero(r.depth), 0.0, kMaxFeatureDepth);
}

const std::vector<std::string>& halfBufferChannels(int half) {
    static const std::vector<std::string> names[2] = {channelsOf(kHalfNames[0]),
                                                      channelsOf(kHalfNames[1])};
    return names[half];
}

std::vector<std::string> layerHalfChannels(int half, const std::string& layer) {
    std::vector<std::string> names;
    for (const char* c : kColourChannels)
        names.push_back(std::string(kHalfNames[half]) + "." + layer + "." + c);
    return names;
}

void halfMeanAndVariance(double sum, double squares, double n, double scale, float& mean,
                         float& variance) {
    mean = n > 0 ? float(sum * scale / n) : 0.0f;
    // The sample variance over n: the variance of the half's mean.
    variance = n >= 2
                   ? float(std::max(0.0, (squares - sum * sum / n) / (n - 1)) / n * scale * scale)
                   : -1.0f;
}

}  // namespace kiln
