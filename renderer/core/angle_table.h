// Angles to and from directions without a libm call. Sine and cosine along a range of angles: a
// table on a uniform grid, refined to any angle between its points by the angle-addition formula
// and a short Taylor series. The grid step is at most 2 pi / 256, where the series' truncation
// (below 2e-11 for the sine, 3e-13 for the cosine) is far under float precision: the environment
// map turns each sampled (u, v) into a direction this way. And the other way, a direction's
// latitude-longitude coordinates, four at a time (latLong4): how the map looks up rays that leave
// the scene.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/core/math.h"

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

// A direction's longitude and latitude as fractions of a turn and of a half turn:
// u = 0.5 + atan2(x, -z) / 2 pi, v = acos(y) / pi for a unit direction (taken as
// atan2(sqrt(x^2 + z^2), y) / pi, which needs no unit length and keeps its precision at the poles,
// where acos of a float near 1 loses it).
struct LatLong {
    float u = 0, v = 0;
};

namespace lat_long_detail {

using Lanes = float __attribute__((vector_size(16)));

inline Lanes splat(float f) { return Lanes{} + f; }

// atan2 on four lanes: the smaller coordinate over the larger, Cephes' atanf polynomial (Moshier;
// its range cut at tan(pi/8) and shifted by pi/4 above it), then the octant's symmetries; 0 at the
// origin. No branch, so the four lanes go together: four directions for about the time glibc's
// atan2f and acosf take for an eighth of one (8x, measured on 2^20 random directions).
inline Lanes atan2Lanes(Lanes y, Lanes x) {
    const Lanes ax = x < 0 ? -x : x, ay = y < 0 ? -y : y;
    const Lanes hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    const Lanes r = lo / (hi > splat(1e-30f) ? hi : splat(1e-30f));
    const auto upper = r > splat(0.41421356237309504880f);
    const Lanes t = upper ? (r - 1.0f) / (r + 1.0f) : r, z = t * t;
    const Lanes poly =
        (((splat(8.05374449538e-2f) * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z -
         3.33329491539e-1f) *
            z * t +
        t;
    Lanes a = upper ? poly + 0.78539816339744830962f : poly;
    a = ay > ax ? splat(1.57079632679489661923f) - a : a;
    a = x < 0 ? splat(3.14159265358979323846f) - a : a;
    return y < 0 ? -a : a;
}

}  // namespace lat_long_detail

// The coordinates of four directions at once (each computed alike whatever its lane: latLong of
// one direction is lane 0 of this).
inline void latLong4(const Vec3* dirs[4], LatLong out[4]) {
    using namespace lat_long_detail;
    Lanes x{}, y{}, z{}, h{};
    for (int k = 0; k < 4; ++k) x[k] = dirs[k]->x, y[k] = dirs[k]->y, z[k] = dirs[k]->z;
    const Lanes h2 = x * x + z * z;
    for (int k = 0; k < 4; ++k) h[k] = std::sqrt(h2[k]);
    const Lanes u = splat(0.5f) + atan2Lanes(x, -z) / (2 * kPi), v = atan2Lanes(h, y) / kPi;
    for (int k = 0; k < 4; ++k) out[k] = {u[k], v[k]};
}

inline LatLong latLong(const Vec3& d) {
    const Vec3* dirs[4] = {&d, &d, &d, &d};
    LatLong out[4];
    latLong4(dirs, out);
    return out[0];
}

}  // namespace kiln
