// A from-scratch BVH over boxes: binned SAH (default) or the CS184 mean-centroid / midpoint splits,
// flattened depth-first nodes, near-child-first traversal. It knows nothing about primitives: the
// caller supplies their boxes at build time and a test function at traversal time.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "renderer/core/math.h"
#include "renderer/core/ray.h"

namespace kiln {

struct BvhNode {
    Bounds3 box;
    uint32_t offset = 0;  // leaf: first primitive in order; interior: index of the second child
    uint16_t count = 0;   // > 0 for leaves
    uint8_t axis = 0;     // split axis, for near-child-first order
    uint8_t pad = 0;
};
static_assert(sizeof(BvhNode) == 32);

struct BvhStatistics {
    uint64_t nodes = 0, leaves = 0, maxDepth = 0;
    double sahCost = 0;  // traversal cost 1, intersection cost 1, relative to the root area
};

struct TraversalCounters {
    uint64_t boxTests = 0, primTests = 0;
};

class Bvh {
  public:
    void build(const std::vector<Bounds3>& primBounds, const ReferenceBvhOptions& options);
    BvhStatistics statistics() const;
    const Bounds3& bounds() const { return nodes_.empty() ? empty_ : nodes_[0].box; }
    uint64_t memoryBytes() const {
        return nodes_.size() * sizeof(BvhNode) + order_.size() * sizeof(uint32_t);
    }

    // testPrim(primIndex, ray) returns true on a hit and shortens ray.tMax itself.
    template <bool AnyHit, typename TestPrim>
    bool traverse(Ray& ray, TestPrim&& testPrim, TraversalCounters* counters = nullptr) const;

  private:
    uint32_t buildRecursive(const std::vector<Bounds3>& boxes, std::vector<Vec3>& centroids,
                            uint32_t begin, uint32_t end, const ReferenceBvhOptions& options,
                            uint32_t depth);
    std::vector<BvhNode> nodes_;
    std::vector<uint32_t> order_;
    Bounds3 empty_;
};

// Slab test; tMax is inflated by 1 + 2*gamma(3) so rounding never culls a box the ray touches
// (pbrt).
inline bool rayBoxTest(const Bounds3& b, const Vec3& org, const Vec3& invDir, const int dirNeg[3],
                       float tMin, float tMax) {
    constexpr float kInflate = 1.0f + 2.0f * gamma(3);
    float tx0 = ((dirNeg[0] ? b.hi.x : b.lo.x) - org.x) * invDir.x;
    float tx1 = ((dirNeg[0] ? b.lo.x : b.hi.x) - org.x) * invDir.x * kInflate;
    float ty0 = ((dirNeg[1] ? b.hi.y : b.lo.y) - org.y) * invDir.y;
    float ty1 = ((dirNeg[1] ? b.lo.y : b.hi.y) - org.y) * invDir.y * kInflate;
    float tz0 = ((dirNeg[2] ? b.hi.z : b.lo.z) - org.z) * invDir.z;
    float tz1 = ((dirNeg[2] ? b.lo.z : b.hi.z) - org.z) * invDir.z * kInflate;
    // NaN from 0 * inf (ray origin on a slab plane, direction parallel) must not reject: max/min
    // skip it.
    float t0 = std::max(std::max(tx0 == tx0 ? tx0 : tMin, ty0 == ty0 ? ty0 : tMin),
                        std::max(tz0 == tz0 ? tz0 : tMin, tMin));
    float t1 = std::min(std::min(tx1 == tx1 ? tx1 : tMax, ty1 == ty1 ? ty1 : tMax),
                        std::min(tz1 == tz1 ? tz1 : tMax, tMax));
    return t0 <= t1;
}

template <bool AnyHit, typename TestPrim>
bool Bvh::traverse(Ray& ray, TestPrim&& testPrim, TraversalCounters* counters) const {
    if (nodes_.empty()) return false;
    Vec3 invDir(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z);
    int dirNeg[3] = {invDir.x < 0, invDir.y < 0, invDir.z < 0};
    uint32_t stack[128];
    int top = 0;
    uint32_t current = 0;
    bool hit = false;
    uint64_t boxTests = 0, primTests = 0;
    while (true) {
        const BvhNode& node = nodes_[current];
        ++boxTests;
        if (rayBoxTest(node.box, ray.origin, invDir, dirNeg, ray.tMin, ray.tMax)) {
            if (node.count > 0) {
                for (uint32_t i = 0; i < node.count; ++i) {
                    ++primTests;
                    if (testPrim(order_[node.offset + i], ray)) {
                        hit = true;
                        if constexpr (AnyHit) {
                            if (counters)
                                counters->boxTests += boxTests, counters->primTests += primTests;
                            return true;
                        }
                    }
                }
                if (top == 0) break;
                current = stack[--top];
            } else if (dirNeg[node.axis]) {
                stack[top++] = current + 1;
                current = node.offset;
            } else {
                stack[top++] = node.offset;
                current = current + 1;
            }
        } else {
            if (top == 0) break;
            current = stack[--top];
        }
    }
    if (counters) counters->boxTests += boxTests, counters->primTests += primTests;
    return hit;
}

}  // namespace kiln
