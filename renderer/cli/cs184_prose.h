// The words of kiln report cs184: what each task of the course asks and how kiln does it (the
// formulas, the estimators and their pdfs), and for each figure a paragraph filled with what this
// run measured. Nothing here holds a measured number: every number comes from the results.
#pragma once

#include <string>
#include <vector>

#include "renderer/cli/cs184_figures.h"
#include "renderer/cli/cs184_shot.h"

namespace kiln::cs184 {

// What the task (or, task 0, the part) is and how kiln does it; empty where there is nothing to
// say beyond the figures.
std::string taskIntro(int part, int task);

// One scene's images of a figure, in the figure's shot order (layers included: their measures
// are the layer's).
struct SceneShots {
    std::string scene;  // its file name
    std::vector<ShotResult> shots;
};
// The paragraphs that discuss one figure's images with their measured numbers.
std::vector<std::string> figureProse(const Figure& figure, const std::vector<SceneShots>& scenes);

// Uniform hemisphere against light importance sampling, scene by scene (same rays).
std::vector<std::string> directComparison(const std::vector<SceneShots>& hemisphere,
                                          const std::vector<SceneShots>& importance);

// One row of the BVH timing table.
struct TimingRow {
    std::string mesh, traversal;
    uint64_t primitives = 0;
    ShotResult shot;
    double fullFramePixels = 0;  // the course's 800x600 frame
    double coveredPixels = 0;    // what the command rendered (a crop for brute force)
    int spp = 1;
    // Seconds of one 800x600 frame at 1 sample, from the measured rays per second.
    double frameSeconds() const;
};
std::vector<std::string> timingProse(const std::vector<TimingRow>& rows, double floorSeconds);

// "1.23" with the given digits after the point.
std::string fixed(double v, int digits);

}  // namespace kiln::cs184
