#include "renderer/adaptive.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace kiln {

namespace {

// The shortest text that reads back as the same float.
std::string shortest(float v) {
    char text[32];
    auto end = std::to_chars(text, text + sizeof text, v).ptr;
    return std::string(text, end);
}

}  // namespace

std::string RenderSettings::adaptiveText() const {
    if (adaptiveBatch > 0) return std::to_string(adaptiveBatch) + " " + shortest(adaptiveTolerance);
    if (noiseThreshold > 0)
        return "noise " + shortest(noiseThreshold) + " min " + std::to_string(adaptiveMinSpp);
    return "off";
}

double pixelRelativeError(const Film& film, int x, int y) {
    double n = film.samples(x, y);
    if (n < 2) return std::numeric_limits<double>::infinity();
    double mu = film.luminanceSum(x, y) / n;
    return std::sqrt(relativeSquaredError(film.luminanceVariance(x, y), mu));
}

namespace {

// CS184's test on the sample illuminance: the 95 % confidence interval within TOL of the mean.
bool cs184Converges(const Film& film, float tolerance, int x, int y) {
    double n = film.samples(x, y);
    if (n < 2) return false;
    double s1 = film.luminanceSum(x, y), s2 = film.luminanceSquareSum(x, y);
    double mu = s1 / n, var = std::max(0.0, (s2 - s1 * s1 / n) / (n - 1));
    return 1.96 * std::sqrt(var / n) <= tolerance * mu;
}

}  // namespace

bool adaptiveConverges(const Film& film, const RenderSettings& settings, int x, int y) {
    if (settings.adaptiveBatch > 0) return cs184Converges(film, settings.adaptiveTolerance, x, y);
    return pixelRelativeError(film, x, y) <= settings.noiseThreshold;
}

}  // namespace kiln
