// Caustic guiding of diffuse bounces. Light that reaches a diffuse surface by way of a glossy or
// specular one (the highlight of a chrome object thrown onto a wall) arrives from a few small
// spots, which cosine sampling rarely hits: each hit is a firefly. Before the render, photons
// traced from the emitting surfaces record where such light lands and the point it last left; a
// diffuse vertex near landed photons then draws a share of its bounces towards those points (one
// cone around the direction to each), the rest by cosine, weighing both densities in every MIS
// weight. It stays unbiased whatever the photons found (Jensen's importance-driven path tracing
// with a photon map, 1995). The guide is frozen before the first pixel, so every sample is still a
// pure function of (seed, pixel, sample index): images stay identical for any threads, tiles,
// shards or resume.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/core/math.h"

namespace kiln {

// A caustic photon: where it landed on a diffuse surface, the point of the glossy or specular
// surface it came from, and its power (luminance).
struct GuideRecord {
    Vec3 p;
    Vec3 from;
    float power = 0;
};

// The photons that landed in one small region: a vertex there is guided by a mixture of cones,
// one around the direction to each photon's source point, chosen by power.
class GuideLeaf {
  public:
    // Half-angle of each cone, about 3.6 degrees: the best of 8.1, 5.7 and 3.6 on the peer
    // benchmark's chrome bunny (docs/performance.md).
    static constexpr float kConeCos = 0.998f;
    GuideLeaf(const GuideRecord* records, size_t count, const Bounds3& bounds);
    bool covers(const Vec3& p) const { return bounds_.contains(p); }
    // A direction from x towards one photon's source (u picks the photon) and the mixture's
    // solid-angle density there.
    Vec3 sample(const Vec3& x, float u, float u1, float u2, float& pdf) const;
    float pdf(const Vec3& x, const Vec3& dir) const;

  private:
    static float widestCos(float sinSubtended);
    bool mayMeetCone(const Vec3& x, const Vec3& dir) const;
    // The sources by coordinate (the density's loop over them vectorises) and their probabilities.
    std::vector<float> sourceX_, sourceY_, sourceZ_, pmf_, cdf_;
    // Every direction from a point in bounds_ that meets a cone lies within this cone (a single
    // dot product rejects the rest): around the line between the centres of the landing and the
    // source points, as wide as the two spheres around them subtend, plus a cone's half-angle.
    Vec3 reachAxis_;
    float reachCos_ = -1;
    // A sphere around the sources: from x, only directions within the angle it subtends, plus a
    // cone's half-angle, can meet a cone.
    Vec3 sourceCentre_;
    float sourceRadius_ = 0;
    Bounds3 bounds_;
};

class GuideField {
  public:
    struct Stats {
        size_t records = 0, leaves = 0, largestLeaf = 0;
    };
    GuideField() = default;
    // A kd-tree over the records' landing points, split at the median of the longest side until
    // a leaf holds at most leafRecords; looked up through a grid. The same records in the same
    // order give the same field bit for bit.
    GuideField(std::vector<GuideRecord> records, size_t leafRecords);
    // The leaf whose photons surround p (found through p's grid cell), else nullptr (cosine
    // sampling alone).
    const GuideLeaf* leafAt(const Vec3& p) const;
    const Stats& stats() const { return stats_; }

  private:
    struct Node {
        float split = 0;
        int axis = -1;       // -1: a leaf
        uint32_t index = 0;  // inner: the first child (the second follows it); leaf: into leaves_
    };
    void build(std::vector<GuideRecord>& records, size_t begin, size_t end, size_t nodeIndex,
               size_t leafRecords, int depth);
    static float medianSplit(std::vector<GuideRecord>& records, size_t begin, size_t end, int axis);
    uint32_t treeLeaf(const Vec3& p) const;
    void buildGrid(const Bounds3& bounds);
    std::vector<Node> nodes_;
    std::vector<GuideLeaf> leaves_;
    // Cells of a grid over the landing points: the leaf whose kd-tree region holds the cell's
    // centre (most lookups need no walk down the tree).
    Vec3 gridOrigin_, gridScale_;
    size_t gridSize_[3] = {0, 0, 0};
    std::vector<uint32_t> grid_;
    Stats stats_;
};

// The share of a guided vertex's bounces drawn from its leaf's cones; the rest are cosine samples,
// which keep every direction the BSDF reaches sampled. Measured on the chrome bunny: 0.1-0.2 reach
// equal error soonest (a guided bounce mostly finds the glossy object, a costlier path); 0.25 and
// more spend too many bounces there.
constexpr float kGuideFraction = 0.15f;

}  // namespace kiln
