#include "integrators/guiding.h"

#include <algorithm>
#include <cmath>

#include "renderer/core/warp.h"

namespace kiln {
namespace {

constexpr int kMaxDepth = 64;
constexpr float kBoundsMargin = 0.25f;  // of a leaf's longest side, around its landing points
constexpr float kGridCells = 32;        // along the longest side of the landing points' box

}  // namespace

GuideLeaf::GuideLeaf(const GuideRecord* records, size_t count, const Bounds3& bounds)
    : bounds_(bounds) {
    double total = 0;
    for (size_t i = 0; i < count; ++i) total += records[i].power;
    double running = 0;
    Bounds3 around;
    for (size_t i = 0; i < count; ++i) {
        const GuideRecord& r = records[i];
        sourceX_.push_back(r.from.x), sourceY_.push_back(r.from.y), sourceZ_.push_back(r.from.z);
        double w = total > 0 ? r.power / total : 1.0 / double(count);  // powerless: evenly
        pmf_.push_back(float(w));
        running += w;
        cdf_.push_back(float(running));
        around.extend(r.from);
    }
    cdf_.back() = 1;
    // The reach cone: the sine of its half-angle is (R + r) / distance, plus a cone's half-angle.
    sourceCentre_ = around.centroid();
    for (size_t i = 0; i < count; ++i)
        sourceRadius_ = std::max(sourceRadius_, length(records[i].from - sourceCentre_));
    sourceRadius_ *= 1 + 1e-4f;
    float r = 0.5f * length(bounds_.diagonal());
    Vec3 axis = sourceCentre_ - bounds_.centroid();
    float dist = length(axis);
    if (dist > 0 && (sourceRadius_ + r) < dist) {
        reachAxis_ = axis / dist;
        reachCos_ = widestCos((sourceRadius_ + r) / dist);
    }
}

// cos(asin(s) + the cone's half-angle): the widest angle from the centre of a sphere that
// subtends asin(s) at which a direction can still meet a cone around a point inside it.
float GuideLeaf::widestCos(float sinSubtended) {
    static const float coneSin = std::sqrt(1 - kConeCos * kConeCos);
    return std::sqrt(1 - sinSubtended * sinSubtended) * kConeCos - sinSubtended * coneSin;
}

bool GuideLeaf::mayMeetCone(const Vec3& x, const Vec3& dir) const {
    Vec3 d = sourceCentre_ - x;
    float dist2 = dot(d, d), r2 = sourceRadius_ * sourceRadius_;
    if (dist2 <= r2) return true;
    float cosMax = widestCos(std::sqrt(r2 / dist2));
    float c = dot(dir, d);
    return cosMax <= 0 || (c > 0 && c * c >= cosMax * cosMax * dist2);
}

Vec3 GuideLeaf::sample(const Vec3& x, float u, float u1, float u2, float& pdf) const {
    size_t j = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    j = std::min(j, cdf_.size() - 1);
    Vec3 source(sourceX_[j], sourceY_[j], sourceZ_[j]);
    Vec3 dir = Frame(normalize(source - x)).toWorld(uniformCone(u1, u2, kConeCos));
    pdf = this->pdf(x, dir);
    return dir;
}

float GuideLeaf::pdf(const Vec3& x, const Vec3& dir) const {
    if (reachCos_ > 0 && dot(dir, reachAxis_) < reachCos_) return 0;
    if (!mayMeetCone(x, dir)) return 0;
    // Inside cone j when the angle to the source's direction d is small enough:
    // dot(dir, d) >= kConeCos |d|, squared for the unnormalised d (no square root per cone).
    const float cos2 = kConeCos * kConeCos;
    const size_t n = pmf_.size();
    const float* sx = sourceX_.data();
    const float* sy = sourceY_.data();
    const float* sz = sourceZ_.data();
    const float* w = pmf_.data();
    // Four running sums in a fixed order, the same bits every run (shaped for a 4-wide register;
    // GCC at -O3 without -march still compiles it to scalar code).
    float inside[4] = {0, 0, 0, 0};
    for (size_t j = 0; j < n; j += 4)
        for (size_t k = 0; k < 4; ++k) {
            size_t i = std::min(j + k, n - 1);
            float dx = sx[i] - x.x, dy = sy[i] - x.y, dz = sz[i] - x.z;
            float c = dir.x * dx + dir.y * dy + dir.z * dz;
            float d2 = dx * dx + dy * dy + dz * dz;
            bool hit = (c > 0) & (c * c >= cos2 * d2) & (j + k < n);
            inside[k] += hit ? w[i] : 0.0f;
        }
    return ((inside[0] + inside[1]) + (inside[2] + inside[3])) * uniformConePdf(kConeCos);
}

GuideField::GuideField(std::vector<GuideRecord> records, size_t leafRecords) {
    stats_.records = records.size();
    if (records.empty()) return;
    Bounds3 landing;
    for (const GuideRecord& r : records) landing.extend(r.p);
    nodes_.emplace_back();
    build(records, 0, records.size(), 0, std::max<size_t>(1, leafRecords), 0);
    buildGrid(landing);
}

// Where to split records [begin, end) along axis (whose extent is not zero): at the median, points
// equal to it going right (treeLeaf's rule), unless more than half lie on the median's plane (a
// wall), then just above that plane, so both sides keep points.
float GuideField::medianSplit(std::vector<GuideRecord>& records, size_t begin, size_t end,
                              int axis) {
    size_t mid = begin + (end - begin) / 2;
    auto byAxis = [axis](const GuideRecord& a, const GuideRecord& b) {
        return a.p[axis] < b.p[axis];
    };
    std::nth_element(records.begin() + long(begin), records.begin() + long(mid),
                     records.begin() + long(end), byAxis);
    float split = records[mid].p[axis];
    bool below = false;
    float above = kInfinity;
    for (size_t i = begin; i < end; ++i) {
        float v = records[i].p[axis];
        below |= v < split;
        if (v > split) above = std::min(above, v);
    }
    return below ? split : above;
}

void GuideField::build(std::vector<GuideRecord>& records, size_t begin, size_t end,
                       size_t nodeIndex, size_t leafRecords, int depth) {
    Bounds3 bounds;
    for (size_t i = begin; i < end; ++i) bounds.extend(records[i].p);
    Vec3 extent = bounds.diagonal();
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    if (end - begin > leafRecords && depth < kMaxDepth && extent[axis] > 0) {
        float split = medianSplit(records, begin, end, axis);
        auto leftEnd = std::partition(records.begin() + long(begin), records.begin() + long(end),
                                      [&](const GuideRecord& r) { return r.p[axis] < split; });
        size_t left = size_t(leftEnd - records.begin());
        uint32_t first = uint32_t(nodes_.size());
        nodes_[nodeIndex] = Node{split, axis, first};
        nodes_.emplace_back();
        nodes_.emplace_back();
        build(records, begin, left, first, leafRecords, depth + 1);
        build(records, left, end, first + 1, leafRecords, depth + 1);
        return;
    }
    // The landing points' box, grown: vertices on the same surface just beside them, and rounding
    // across a plane the points all lie in.
    Vec3 margin =
        Vec3(kBoundsMargin * maxComponent(extent)) + (abs(bounds.lo) + abs(bounds.hi)) * 1e-5f;
    bounds.lo -= margin, bounds.hi += margin;
    nodes_[nodeIndex] = Node{0, -1, uint32_t(leaves_.size())};
    leaves_.emplace_back(&records[begin], end - begin, bounds);
    ++stats_.leaves;
    stats_.largestLeaf = std::max(stats_.largestLeaf, end - begin);
}

const GuideLeaf* GuideField::leafAt(const Vec3& p) const {
    Vec3 c = (p - gridOrigin_) * gridScale_;
    if (!(c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < float(gridSize_[0]) &&
          c.y < float(gridSize_[1]) && c.z < float(gridSize_[2])))
        return nullptr;
    uint32_t leaf = grid_[(size_t(c.z) * gridSize_[1] + size_t(c.y)) * gridSize_[0] + size_t(c.x)];
    // A cell crossed by a split of the tree: p may lie in the other leaf.
    if (!leaves_[leaf].covers(p)) leaf = treeLeaf(p);
    return leaves_[leaf].covers(p) ? &leaves_[leaf] : nullptr;
}

uint32_t GuideField::treeLeaf(const Vec3& p) const {
    const Node* n = &nodes_[0];
    while (n->axis >= 0) n = &nodes_[n->index + (p[n->axis] < n->split ? 0 : 1)];
    return n->index;
}

void GuideField::buildGrid(const Bounds3& landing) {
    // Cubic cells, kGridCells along the longest side; the box grown by the leaves' margin.
    Vec3 extent = landing.diagonal();
    float side = std::max(maxComponent(extent), 1e-6f) / kGridCells;
    Vec3 margin = Vec3(kBoundsMargin * maxComponent(extent) + side);
    gridOrigin_ = landing.lo - margin;
    Vec3 span = extent + margin * 2.0f;
    gridScale_ = Vec3(1 / side);
    for (int a = 0; a < 3; ++a) gridSize_[a] = size_t(std::ceil(span[a] / side));
    grid_.resize(gridSize_[0] * gridSize_[1] * gridSize_[2]);
    for (size_t z = 0; z < gridSize_[2]; ++z)
        for (size_t y = 0; y < gridSize_[1]; ++y)
            for (size_t x = 0; x < gridSize_[0]; ++x) {
                Vec3 centre =
                    gridOrigin_ + Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f) * side;
                grid_[(z * gridSize_[1] + y) * gridSize_[0] + x] = treeLeaf(centre);
            }
}

}  // namespace kiln
