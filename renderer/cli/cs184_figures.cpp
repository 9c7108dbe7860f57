#include "renderer/cli/cs184_figures.h"

#include <fmt/format.h>

namespace kiln::cs184 {

const std::vector<Task>& courseTasks() {
    static const std::vector<Task> tasks = {
        {1, 0, "Part 1: Ray Generation and Scene Intersection"},
        {1, 1, "Task 1: Generating Camera Rays"},
        {1, 2, "Task 2: Generating Pixel Samples"},
        {1, 3, "Task 3: Ray-Triangle Intersection"},
        {1, 4, "Task 4: Ray-Sphere Intersection"},
        {2, 0, "Part 2: Bounding Volume Hierarchy"},
        {2, 1, "Task 1: Constructing the BVH"},
        {2, 2, "Task 2: Intersecting the Bounding Box"},
        {2, 3, "Task 3: Intersecting the BVH"},
        {3, 0, "Part 3: Direct Illumination"},
        {3, 1, "Task 1: Diffuse BSDF"},
        {3, 2, "Task 2: Zero-bounce Illumination"},
        {3, 3, "Task 3: Direct Lighting with Uniform Hemisphere Sampling"},
        {3, 4, "Task 4: Direct Lighting by Importance Sampling Lights"},
        {4, 0, "Part 4: Global Illumination"},
        {4, 1, "Task 1: Sampling with Diffuse BSDF"},
        {4, 2, "Task 2: Global Illumination"},
        {4, 3, "Task 3: Global Illumination with Russian Roulette"},
        {5, 0, "Part 5: Adaptive Sampling"},
    };
    return tasks;
}

namespace {

Shot shot(std::string id, std::string label, std::string flags, int courseSpp = 1,
          SppRule rule = SppRule::Course, int courseBatch = 0, std::string layer = "") {
    Shot s;
    s.id = std::move(id), s.label = std::move(label), s.flags = std::move(flags);
    s.courseSpp = courseSpp, s.rule = rule, s.courseBatch = courseBatch;
    s.layer = std::move(layer);
    return s;
}

Shot scaled(const std::string& id, const std::string& label, const std::string& flags) {
    return shot(id, label, flags, 1024, SppRule::Scaled);
}

}  // namespace

std::vector<Figure> courseFigures() {
    std::vector<Figure> f;
    f.push_back(
        {"normals", 1, 4, "Normal shading", {shot("normals", "normal shading", "-i normals")}});
    f.push_back(
        {"zero", 3, 2, "Zero-bounce illumination", {shot("m0", "-m 0: emission only", "-m 0")}});
    f.push_back({"hemisphere",
                 3,
                 3,
                 "Uniform hemisphere sampling",
                 {shot("hemisphere", "uniform hemisphere sampling (-H)", "-l 8 -m 1 -H", 16)}});
    f.push_back(
        {"importance",
         3,
         4,
         "Importance sampling the lights, the same rays as -H",
         {shot("importance", "light importance sampling", "-l 8 -m 1 --sampling light", 16)}});
    Figure lightRays{"lightrays", 3, 4, "1, 4, 16 and 64 light rays at 1 sample per pixel", {}};
    for (int l : {1, 4, 16, 64})
        lightRays.shots.push_back(shot(fmt::format("l{}", l), fmt::format("-l {}", l),
                                       fmt::format("-l {} -m 1 --sampling light", l)));
    f.push_back(lightRays);
    f.push_back(
        {"gi",
         4,
         2,
         "Global illumination, and its direct and indirect parts",
         {scaled("gi", "global illumination", "-l 4 -m 5 --aov direct,indirect"),
          shot("gi.direct", "direct illumination only", "", 1024, SppRule::Scaled, 0, "direct"),
          shot("gi.indirect", "indirect illumination only", "", 1024, SppRule::Scaled, 0,
               "indirect")}});
    Figure bounce{"bounce", 4, 2, "The m-th bounce of light only (-o 0)", {}};
    Figure depth{"depth", 4, 2, "max_ray_depth 0 to 5, bounces accumulated", {}};
    Figure roulette{"roulette", 4, 3, "Russian roulette, max_ray_depth 0, 1, 2, 3, 4 and 100", {}};
    for (int m : {0, 1, 2, 3, 4, 5, 100}) {
        if (m <= 5) {
            bounce.shots.push_back(scaled(fmt::format("m{}o0", m), fmt::format("bounce {}", m),
                                          fmt::format("-l 4 -o 0 -m {}", m)));
            depth.shots.push_back(scaled(fmt::format("m{}", m), fmt::format("-m {}", m),
                                         fmt::format("-l 4 -m {}", m)));
        }
        if (m != 5)
            roulette.shots.push_back(scaled(fmt::format("rr{}", m),
                                            fmt::format("-m {}, --rr fixed", m),
                                            fmt::format("-l 4 -m {} --rr fixed", m)));
    }
    f.push_back(bounce);
    f.push_back(depth);
    Figure spp{"spp", 4, 2, "Samples per pixel 1 to 1024, 4 light rays", {}};
    for (int s : {1, 2, 4, 8, 16, 64})
        spp.shots.push_back(
            shot(fmt::format("s{}", s), fmt::format("-s {}", s), "-l 4 -m 5", s, SppRule::Sweep));
    spp.shots.push_back(shot("s1024", "-s 1024", "-l 4 -m 5", 1024, SppRule::Top));
    f.push_back(spp);
    f.push_back(roulette);
    f.push_back({"adaptive", 5, 0, "Adaptive sampling and its sample-rate image", {[] {
                     Shot s = shot("adaptive", "adaptive sampling", "-l 1 -m 5", 2048,
                                   SppRule::Scaled, 64);
                     s.boost = 4;
                     return s;
                 }()}});
    return f;
}

}  // namespace kiln::cs184
