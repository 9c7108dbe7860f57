#include "renderer/cli/cs184_planner.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "renderer/cli/cs184_shot.h"

namespace kiln::cs184 {

const std::vector<Size>& reportSizes() {
    static const std::vector<Size> sizes = {{800, 600}, {640, 480}, {480, 360}, {320, 240},
                                            {240, 180}, {160, 120}, {80, 60}};
    return sizes;
}

namespace {

int largestPowerOfTwoAtMost(int n) {
    int p = 1;
    while (p * 2 <= n) p *= 2;
    return p;
}

std::string tolerance(double t) {
    std::string s = std::to_string(t);
    s.erase(s.find_last_not_of('0') + 1);
    return s.back() == '.' ? s + "0" : s;
}

}  // namespace

ShotPlan planShot(const Shot& shot, double scale, int topSpp) {
    ShotPlan p;
    switch (shot.rule) {
        case SppRule::Course:
            p.spp = shot.courseSpp;
            break;
        case SppRule::Scaled:
            p.spp =
                std::max(1, int(std::lround(shot.courseSpp * std::min(1.0, scale * shot.boost))));
            break;
        case SppRule::Sweep:
            p.spp = 3 * shot.courseSpp <= 2 * topSpp ? shot.courseSpp : 0;
            break;
        case SppRule::Top:
            p.spp = topSpp;
            break;
    }
    if (p.spp == 0) return p;
    p.flags = "-s " + std::to_string(p.spp);
    if (shot.courseBatch > 0) {
        // The cap at least four batches: pixels must be able to stop before it, or the rate
        // image is the cap everywhere.
        p.batch = p.spp >= 4 * shot.courseBatch ? shot.courseBatch
                                                : std::max(4, largestPowerOfTwoAtMost(p.spp / 4));
        p.spp = std::max(p.spp, 4 * p.batch);
        p.flags = "-s " + std::to_string(p.spp) + " -a " + std::to_string(p.batch) + " " +
                  tolerance(shot.tolerance);
    }
    if (!shot.flags.empty()) p.flags += " " + shot.flags;
    return p;
}

int nominalTop(const Figure& sweep, double scale) {
    int top = 0, largestStep = 1;
    for (const Shot& s : sweep.shots)
        if (s.rule == SppRule::Top) top = std::max(1, int(std::lround(s.courseSpp * scale)));
    for (const Shot& s : sweep.shots)
        if (s.rule == SppRule::Sweep && 3 * s.courseSpp <= 2 * top)
            largestStep = std::max(largestStep, s.courseSpp);
    return std::max(top, (3 * largestStep + 1) / 2);
}

double modelRaysPerSample(const std::string& flags) {
    // The planner asks for the same few flag sets thousands of times while it fits the budget.
    static std::map<std::string, double> known;
    if (auto it = known.find(flags); it != known.end()) return it->second;
    RenderJobOptions o = jobForFlags(flags);
    double rays = 1;
    if (o.integrator != IntegratorKind::Normals)
        rays = 1 + std::min(o.path.maxDepth, 6) * (std::max(1, o.path.lightSamples) + 1.0);
    return known[flags] = rays;
}

std::string sppFreeKey(const std::string& flags) {
    std::vector<std::string> w = words(flags);
    std::string key;
    for (size_t i = 0; i < w.size(); ++i) {
        if (w[i] == "-s") {
            ++i;
            continue;
        }
        if (w[i] == "-a") {
            i += 2;
            continue;
        }
        key += (key.empty() ? "" : " ") + w[i];
    }
    return key;
}

double Throughput::raysPerSample(const std::string& flags) const {
    auto it = raysPerSample_.find(sppFreeKey(flags));
    return it != raysPerSample_.end() ? it->second : modelRaysPerSample(flags);
}

void Throughput::record(const std::string& key, double rays, double seconds) {
    records_.push_back({key, rays, seconds});
}

double Throughput::secondsPerRay() const {
    // The last few renders: the machine's present load, not the run's average.
    constexpr size_t kRecent = 6;
    double rays = 0, seconds = 0;
    for (size_t i = records_.size() > kRecent ? records_.size() - kRecent : 0; i < records_.size();
         ++i)
        rays += records_[i].rays, seconds += records_[i].seconds;
    return rays > 0 ? seconds / rays : 1e-7;
}

double Throughput::secondsPerRay(const std::string& key) const {
    for (auto it = records_.rbegin(); it != records_.rend(); ++it)
        if (it->key == key && it->rays > 0) return it->seconds / it->rays;
    return secondsPerRay();
}

double Planner::predictShot(size_t scene, const ShotPlan& plan, Size size) const {
    if (plan.spp == 0) return 0;
    const Throughput& t = throughput_[scene];
    return double(size.width) * size.height * plan.spp * t.raysPerSample(plan.flags) *
           t.secondsPerRay();
}

double Planner::predict(const std::vector<size_t>& figureIndices, Size size, double scale) const {
    double total = 0;
    for (size_t f : figureIndices) {
        int top = nominalTop(figures_[f], scale);
        for (size_t scene = 0; scene < throughput_.size(); ++scene)
            for (const Shot& shot : figures_[f].shots)
                if (shot.layer.empty())
                    total += predictShot(scene, planShot(shot, scale, top), size);
    }
    return total;
}

std::vector<size_t> Planner::allFigures() const {
    std::vector<size_t> all(figures_.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    return all;
}

double Planner::secondsNeeded(Size size) const { return predict(allFigures(), size, kMinScale); }

Size Planner::chooseSize(double seconds) const {
    for (Size s : reportSizes())
        if (secondsNeeded(s) <= seconds) return s;
    return reportSizes().back();
}

double Planner::fitScale(const std::vector<size_t>& figureIndices, Size size,
                         double seconds) const {
    const bool smallest = size.width == reportSizes().back().width;
    double lo = smallest ? kFloorScale : kMinScale, hi = 1;
    if (predict(figureIndices, size, hi) <= seconds) return hi;
    if (predict(figureIndices, size, lo) >= seconds) return lo;
    for (int i = 0; i < 30; ++i) {  // bisection on log(scale)
        double mid = std::sqrt(lo * hi);
        (predict(figureIndices, size, mid) <= seconds ? lo : hi) = mid;
    }
    return lo;
}

int Planner::topSpp(size_t scene, const Shot& top, Size size, double seconds, int floorSpp) const {
    ShotPlan one = planShot(top, 0, 1);
    const Throughput& t = throughput_[scene];
    double perSample = double(size.width) * size.height * t.raysPerSample(one.flags) *
                       t.secondsPerRay(sppFreeKey(one.flags));
    int spp = int(seconds / perSample);
    return std::clamp(spp, (3 * floorSpp + 1) / 2, top.courseSpp);
}

}  // namespace kiln::cs184
