// Chi-square goodness-of-fit for sampling routines: histogram of sampled directions against the
// expected counts integrated from the claimed pdf, low-expectation bins pooled (pbrt, Mitsuba).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/math.h"
#include "renderer/core/sampler.h"

namespace kiln::test {

// Regularised upper incomplete gamma Q(a, x) (Numerical Recipes): the chi-square tail probability
// is Q(dof / 2, statistic / 2).
inline double gammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    double gln = std::lgamma(a);
    if (x < a + 1) {  // series for P
        double sum = 1.0 / a, del = sum, ap = a;
        for (int n = 0; n < 100000; ++n) {
            ap += 1;
            del *= x / ap;
            sum += del;
            if (std::abs(del) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
    }
    double b = x + 1 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;  // continued fraction for Q
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::abs(c) < 1e-300) c = 1e-300;
        d = 1 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - gln) * h;
}

struct Chi2Result {
    double statistic = 0, pValue = 0;
    int dof = 0;
    std::string table;  // the pooled bins, for failure messages
};

// Cells with expected count below 5 are pooled, smallest first, into groups of at least 5
// (Mitsuba's rule): a pdf with sharp edges (area lights) leaves slivers whose integrated
// expectation is poor alone.
inline Chi2Result chi2FromCounts(const std::vector<double>& observed,
                                 const std::vector<double>& expected) {
    Chi2Result r;
    std::vector<size_t> order(observed.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double pooledObs = 0, pooledExp = 0;
    int bins = 0, pooledCells = 0;
    for (size_t i : order) {
        if (expected[i] == 0 && observed[i] == 0) continue;
        if (expected[i] < 5 || pooledExp > 0) {
            pooledObs += observed[i], pooledExp += expected[i];
            ++pooledCells;
            if (pooledExp < 5) continue;
            double d = pooledObs - pooledExp;
            r.statistic += d * d / pooledExp;
            ++bins;
            pooledObs = pooledExp = 0;
            continue;
        }
        double d = observed[i] - expected[i];
        r.statistic += d * d / expected[i];
        ++bins;
    }
    if (pooledObs > 0 ||
        pooledExp > 0) {  // a remainder below 5: cannot be tested alone, fold it in
        double d = pooledObs - pooledExp;
        r.statistic += d * d / std::max(pooledExp, 5.0);
        ++bins;
    }
    r.dof = std::max(1, bins - 1);
    r.pValue = gammaQ(0.5 * r.dof, 0.5 * r.statistic);
    r.table = "chi2 " + std::to_string(r.statistic) + " dof " + std::to_string(r.dof) + " (" +
              std::to_string(pooledCells) + " low cells pooled)";
    return r;
}

// Directions over the whole sphere in (theta, phi) bins (pbrt's layout: fine near the poles, where
// peaked lobes at normal incidence live). sample() returns a unit direction or nothing (a failed
// sample); pdf() is the solid-angle density it claims. Expected counts integrate pdf * sin(theta)
// over each bin with sub x sub midpoints; failed samples have their own bin, expected (1 - integral
// of the pdf).
inline Chi2Result chi2Directions(const std::function<std::optional<Vec3>(Sampler&)>& sample,
                                 const std::function<double(const Vec3&)>& pdf, int samples,
                                 uint64_t seed, int thetaBins = 80, int phiBins = 160,
                                 int sub = 16) {
    std::vector<double> observed(size_t(thetaBins * phiBins) + 1, 0.0),
        expected(observed.size(), 0.0);
    auto binOf = [&](const Vec3& w) {
        double theta = std::acos(std::clamp(double(w.z), -1.0, 1.0));
        int t = std::clamp(int(theta / M_PI * thetaBins), 0, thetaBins - 1);
        double phi = std::atan2(w.y, w.x);
        if (phi < 0) phi += 2 * M_PI;
        int p = std::clamp(int(phi / (2 * M_PI) * phiBins), 0, phiBins - 1);
        return size_t(t * phiBins + p);
    };
    for (int i = 0; i < samples; ++i) {
        Sampler s(seed, uint64_t(i), 0);
        std::optional<Vec3> w = sample(s);
        observed[w ? binOf(*w) : observed.size() - 1] += 1;
    }
    double total = 0;
    double dTheta = M_PI / thetaBins, dPhi = 2 * M_PI / phiBins;
    for (int t = 0; t < thetaBins; ++t)
        for (int p = 0; p < phiBins; ++p) {
            double integral = 0;
            for (int a = 0; a < sub; ++a)
                for (int b = 0; b < sub; ++b) {
                    double theta = (t + (a + 0.5) / sub) * dTheta,
                           phi = (p + (b + 0.5) / sub) * dPhi;
                    double sn = std::sin(theta);
                    integral += sn * pdf(Vec3(float(sn * std::cos(phi)), float(sn * std::sin(phi)),
                                              float(std::cos(theta))));
                }
            integral *= dTheta * dPhi / (sub * sub);
            expected[size_t(t * phiBins + p)] = integral * samples;
            total += integral;
        }
    expected.back() = std::max(0.0, 1 - total) * samples;
    return chi2FromCounts(observed, expected);
}

}  // namespace kiln::test
