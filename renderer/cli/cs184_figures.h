// The CS184 PathTracer write-up as the course asks for it: its five parts and their tasks, with
// the course's headings, and the figures each task shows, every image with the course's setting
// (its -s, -l, -m, -a). kiln report cs184 renders these, sized to its budget (cs184_planner.h).
#pragma once

#include <string>
#include <vector>

namespace kiln::cs184 {

struct Task {
    int part, task;  // task 0: the part's own heading
    std::string heading;
};
// Part headings (task 0) and task headings, in the course's order.
const std::vector<Task>& courseTasks();

// How a shot's -s follows the budget: the course's value always (cheap images whose point is
// the setting itself), the course's value scaled by the budget's fraction, a step of the
// samples-per-pixel sweep (kept only below the sweep's top), or the sweep's top, rendered last
// with whatever the budget has left.
enum class SppRule { Course, Scaled, Sweep, Top };

struct Shot {
    std::string id;     // in the image's file name
    std::string label;  // what the image shows
    std::string flags;  // kiln render flags besides -s, -a, -r, -t, --view and -f
    int courseSpp = 1;
    SppRule rule = SppRule::Course;
    int courseBatch = 0;      // -a BATCH TOL: the course's batch, 0 when not adaptive
    double tolerance = 0.05;  // -a's TOL
    // Scaled: the budget's fraction is multiplied by this (at most the course's -s). Adaptive
    // sampling's cap gets 4: the render takes about half its cap, and a cap near the batch leaves
    // no pixel room to stop early, so the rate image would show nothing.
    int boost = 1;
    std::string layer;        // non-empty: this layer of the previous shot's render
};

struct Figure {
    std::string key;  // what the prose says about it (cs184_prose.h)
    int part, task;
    std::string title;
    std::vector<Shot> shots;
};
// Every figure in page order. The BVH timing table (part 2) is no figure: the report times it.
std::vector<Figure> courseFigures();

// The course's own sizes: the window of the course program and of the BVH timings.
constexpr int kCourseWidth = 800, kCourseHeight = 600;

}  // namespace kiln::cs184
