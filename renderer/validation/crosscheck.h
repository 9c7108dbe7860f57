// Ray-by-ray comparison of two accelerators, with every disagreement classified.
#pragma once

#include <string>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "renderer/core/json.h"
#include "renderer/validation/ray_sets.h"

namespace kiln {

// Thresholds (documented in docs/accelerators.md):
//  - edge: the hit that one side found lies within kEdgeTolerance (barycentric) of an edge or
//  vertex of
//    its triangle, or grazes a sphere's silhouette; there the two watertight-in-their-own-way tests
//    may legitimately choose different neighbours or miss/hit.
//  - coplanar: both hit different primitives at the same distance (|dt|/t <= kTieTolerance):
//  duplicate
//    or touching coplanar surfaces, where the winner is arbitrary.
//  - genuine: anything else, including a same-primitive hit whose distances differ by more than
//    kDistanceTolerance relative plus kUlpAllowance float ulps of the coordinates (absolute).
constexpr float kEdgeTolerance = 1e-5f;
constexpr float kTieTolerance = 1e-5f;
constexpr float kDistanceTolerance = 1e-4f;
constexpr float kUlpAllowance = 64.0f;

enum class Disagreement { None, Edge, Coplanar, Genuine };

struct RayComparison {
    Ray ray;
    Hit a, b;  // closest hits (a: first accelerator, b: second)
    bool occludedA = false, occludedB = false;
    Disagreement kind = Disagreement::None;
    float relativeDt = 0;
    float baryDiff = 0;
    std::string reason;
};

struct CrosscheckCategory {
    RaySetKind kind;
    uint64_t rays = 0, hitsA = 0, hitsB = 0, agree = 0, edge = 0, coplanar = 0, genuine = 0;
    uint64_t samePrim = 0;
    double maxRelativeDt = 0, maxBaryDiff = 0;
    std::vector<RayComparison> worst;  // genuine first, then the largest |dt|/t
};

struct CrosscheckReport {
    std::vector<CrosscheckCategory> categories;
    uint64_t totalGenuine() const {
        uint64_t n = 0;
        for (const auto& c : categories) n += c.genuine;
        return n;
    }
};

// `kiln crosscheck --json`: the scene, each category's counts and worst errors, the genuine total.
Json crosscheckJson(const CrosscheckReport& report, const std::string& scenePath);

RayComparison compareRay(const Scene& scene, const Accelerator& a, const Accelerator& b,
                         const Ray& ray, bool shadowRay);

CrosscheckReport crosscheck(const Scene& scene, const Accelerator& a, const Accelerator& b,
                            size_t raysPerCategory, uint64_t seed, size_t worstToKeep = 5);

std::string formatRay(const Ray& ray);  // exact (hex-float) form, accepted by --replay
// False unless text is 8 numbers and a ray Embree can trace (finite origin and direction, a
// direction that is not zero, 0 <= tmin <= tmax).
bool parseRay(const std::string& text, Ray& ray);

}  // namespace kiln
