#include "integrators/slab_albedo.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "renderer/core/math.h"

namespace kiln {
namespace {

// Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre polynomial's roots). The
// H-function is smooth on (0, 1]: 16 nodes already give its moments to 1e-8.
constexpr int kNodes = 32;

struct Quadrature {
    std::array<double, kNodes> x{}, w{};
};

const Quadrature& gaussLegendre() {
    static const Quadrature q = [] {
        Quadrature out;
        for (int i = 0; i < kNodes; ++i) {
            double z = std::cos(double(kPi) * (i + 0.75) / (kNodes + 0.5)), step = 1, dp = 1;
            while (std::abs(step) > 1e-15) {
                double p1 = 1, p2 = 0;  // P_n(z), P_n-1(z) by the three-term recurrence
                for (int j = 1; j <= kNodes; ++j) {
                    double p3 = p2;
                    p2 = p1;
                    p1 = ((2 * j - 1) * z * p2 - (j - 1) * p3) / j;
                }
                dp = kNodes * (z * p1 - p2) / (z * z - 1);
                step = p1 / dp;
                z -= step;
            }
            out.x[size_t(i)] = (1 - z) / 2;
            out.w[size_t(i)] = 1 / ((1 - z * z) * dp * dp);
        }
        return out;
    }();
    return q;
}

// The table: slab albedos at u = sqrt(1 - omega) = k / kSteps (R falls from 1 at u = 0 to 0 at
// u = 1, nearly linearly in u: R ~ 1 - 2.31 u near 1).
constexpr int kSteps = 256;

const std::array<double, kSteps + 1>& albedoByU() {
    static const std::array<double, kSteps + 1> table = [] {
        std::array<double, kSteps + 1> out{};
        for (int k = 0; k <= kSteps; ++k) {
            double u = double(k) / kSteps;
            out[size_t(k)] = slabAlbedo(1 - u * u);
        }
        return out;
    }();
    return table;
}

}  // namespace

HMoments hFunctionMoments(double omega) {
    // Within 1e-8 of 1 (sqrt(1 - omega) < 1e-4) the iteration would take millions of steps; the
    // conservative limits are within 2e-4 there.
    if (omega > 1 - 1e-8) return {2.0, 2 / std::sqrt(3.0)};
    const Quadrature& q = gaussLegendre();
    const double root = std::sqrt(1 - std::max(omega, 0.0));
    // The H-equation in the form 1 / H(mu) = sqrt(1 - omega) + omega / 2 int_0^1 mu' H(mu') /
    // (mu + mu') dmu', iterated from H = 1: for omega < 1 each step shrinks the error by about
    // 1 - 2.2 sqrt(1 - omega), so the error left is below change / (2.2 sqrt(1 - omega)) (1e-10 at
    // the table's smallest sqrt(1 - omega), 1/256). Rounding keeps the change above 1e-13 there.
    std::array<double, kNodes> h{}, next{};
    h.fill(1.0);
    for (double change = 1; change > 1e-12;) {
        change = 0;
        for (int i = 0; i < kNodes; ++i) {
            double sum = 0;
            for (int j = 0; j < kNodes; ++j)
                sum += q.w[size_t(j)] * q.x[size_t(j)] * h[size_t(j)] /
                       (q.x[size_t(i)] + q.x[size_t(j)]);
            next[size_t(i)] = 1 / (root + omega / 2 * sum);
            change = std::max(change, std::abs(next[size_t(i)] - h[size_t(i)]));
        }
        h = next;
    }
    HMoments m;
    for (int i = 0; i < kNodes; ++i) {
        m.h0 += q.w[size_t(i)] * h[size_t(i)];
        m.h1 += q.w[size_t(i)] * h[size_t(i)] * q.x[size_t(i)];
    }
    return m;
}

double slabAlbedo(double omega) {
    if (omega >= 1) return 1;
    return 1 - 2 * std::sqrt(1 - omega) * hFunctionMoments(omega).h1;
}

float singleScatteringAlbedoFor(float albedo) {
    const auto& r = albedoByU();
    const double a = std::clamp(double(albedo), 0.0, 1.0);
    // The first k with r[k] <= a (r falls with k), and u between k - 1 and k, linear in r.
    const auto it = std::lower_bound(r.begin(), r.end(), a, std::greater<>());
    const int k = std::clamp(int(it - r.begin()), 1, kSteps);
    const double lo = r[size_t(k - 1)], hi = r[size_t(k)];
    const double t = lo > hi ? (lo - a) / (lo - hi) : 0;
    const double u = (k - 1 + t) / kSteps;
    return float(std::max(0.0, 1 - u * u));
}

}  // namespace kiln
