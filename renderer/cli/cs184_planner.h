// How kiln report cs184 spends its budget: the largest image size first (the course's 4:3), then
// the samples of the figures whose -s the budget may scale, refitted before every figure from the
// throughput measured so far in this run (so a machine that gets busier or quieter is followed),
// and the samples-per-pixel sweep's top image last with what is left: the run ends near the
// budget. Experiments stay meaningful: adaptive sampling's cap stays above its batch.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "renderer/cli/cs184_figures.h"

namespace kiln::cs184 {

struct Size {
    int width, height;
};
// The report's sizes, largest first: the course's window down to 80x60.
const std::vector<Size>& reportSizes();
// The size the issue and the course ask the main figures to be at least.
constexpr Size kMainSize{480, 360};

// The least fraction of the course's samples before the image shrinks: the course's 1024
// becomes 16. Below the smallest size the fraction may fall to 1/1024.
constexpr double kMinScale = 1.0 / 64, kFloorScale = 1.0 / 1024;

// A shot's -s (and -a batch) at a budget fraction; spp 0: the shot is left out (a sweep step
// not at most two thirds of the sweep's top).
struct ShotPlan {
    int spp = 0, batch = 0;
    std::string flags;  // kiln render flags besides -r, -t, --view, -f
};
ShotPlan planShot(const Shot& shot, double scale, int topSpp);
// The sweep top at a fraction: the course's -s scaled, at least 1.5 times the largest step kept.
int nominalTop(const Figure& sweep, double scale);

// Rays of one camera sample as a model guesses them before a probe measured them: the camera
// ray, then per vertex the light samples and the next bounce (-m 100 counts as 6 vertices).
double modelRaysPerSample(const std::string& flags);

// What this run measured of one scene: the rays a camera sample of each flag set (without -s)
// traces, from a small probe render per flag set, and the seconds a ray costs, from the recent
// renders (the machine's present load) or the latest render of the same flag set.
class Throughput {
  public:
    void setRaysPerSample(const std::string& key, double rays) { raysPerSample_[key] = rays; }
    double raysPerSample(const std::string& flags) const;
    void record(const std::string& key, double rays, double seconds);
    double secondsPerRay() const;
    double secondsPerRay(const std::string& key) const;

  private:
    struct Record {
        std::string key;
        double rays, seconds;
    };
    std::vector<Record> records_;
    std::map<std::string, double> raysPerSample_;
};

// The key of a flag set: its words without -s N and -a B T.
std::string sppFreeKey(const std::string& flags);

class Planner {
  public:
    Planner(const std::vector<Figure>& figures, size_t scenes)
        : figures_(figures), throughput_(scenes) {}
    Throughput& throughput(size_t scene) { return throughput_[scene]; }

    // Predicted seconds of these figures for every scene at a size and fraction.
    double predict(const std::vector<size_t>& figureIndices, Size size, double scale) const;
    // The largest size whose figures fit the seconds at kMinScale (else the smallest).
    Size chooseSize(double seconds) const;
    // The seconds the figures need at a size at kMinScale (what a budget must leave them).
    double secondsNeeded(Size size) const;
    // The largest fraction (kMinScale.. 1, or down to kFloorScale at the smallest size) whose
    // predicted time for the figures fits the seconds.
    double fitScale(const std::vector<size_t>& figureIndices, Size size, double seconds) const;
    // The sweep top's -s for one scene given the seconds it may take (its same-flag throughput),
    // at least 1.5 times floorSpp, at most the course's.
    int topSpp(size_t scene, const Shot& top, Size size, double seconds, int floorSpp) const;

  private:
    double predictShot(size_t scene, const ShotPlan& plan, Size size) const;
    std::vector<size_t> allFigures() const;
    const std::vector<Figure>& figures_;
    std::vector<Throughput> throughput_;
};

}  // namespace kiln::cs184
