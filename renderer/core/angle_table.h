// Sine and cosine along a range of angles without a libm call: a table on a uniform grid, refined
// to any angle between its points by the angle-addition formula and a short Taylor series. The
// grid step is at most 2 pi / 256, where the series' truncation (below 2e-11 for the sine, 3e-13
// for the cosine) is far under float precision: the environment map turns each sampled (u, v) into
// a direction this way.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace kiln {

class AngleTable {
  public:
    // Angles start + t * span for t in [0, 1], on `steps` intervals.
    AngleTable(double start, double span, int steps) : step_(float(span / steps)), steps_(steps) {
        for (int k = 0; k <= steps; ++k) {
            double a = start + span * k / steps;
            sin_.push_back(float(std::sin(a)));
            cos_.push_back(float(std::cos(a)));
        }
    }
    void sinCos(float t, float& s, float& c) const {
        const float x = t * float(steps_);
        const int k = std::clamp(int(x), 0, steps_ - 1);
        const float d = (x - float(k)) * step_, d2 = d * d;
        const float sd = d * (1 - d2 / 6 * (1 - d2 / 20)), cd = 1 - d2 / 2 * (1 - d2 / 12);
        s = sin_[size_t(k)] * cd + cos_[size_t(k)] * sd;
        c = cos_[size_t(k)] * cd - sin_[size_t(k)] * sd;
    }

  private:
    std::vector<float> sin_, cos_;
    float step_;
    int steps_;
};

}  // namespace kiln
