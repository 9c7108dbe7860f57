#include "renderer/accel/bvh.h"

#include <algorithm>
#include <numeric>

namespace kiln {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kForceMedianDepth =
    64;  // keeps the traversal stack bounded on adversarial input

}  // namespace

void Bvh::build(const std::vector<Bounds3>& primBounds, const ReferenceBvhOptions& options) {
    nodes_.clear();
    order_.resize(primBounds.size());
    std::iota(order_.begin(), order_.end(), 0u);
    if (primBounds.empty()) return;
    std::vector<Vec3> centroids(primBounds.size());
    for (size_t i = 0; i < primBounds.size(); ++i) centroids[i] = primBounds[i].centroid();
    nodes_.reserve(2 * primBounds.size() / std::max(1, options.maxLeafSize) + 1);
    buildRecursive(primBounds, centroids, 0, uint32_t(primBounds.size()), options, 0);
    nodes_.shrink_to_fit();
}

uint32_t Bvh::buildRecursive(const std::vector<Bounds3>& boxes, std::vector<Vec3>& centroids,
                             uint32_t begin, uint32_t end, const ReferenceBvhOptions& options,
                             uint32_t depth) {
    uint32_t index = uint32_t(nodes_.size());
    nodes_.emplace_back();
    Bounds3 box, centroidBox;
    for (uint32_t i = begin; i < end; ++i) {
        box.extend(boxes[order_[i]]);
        centroidBox.extend(centroids[order_[i]]);
    }
    nodes_[index].box = box;
    uint32_t count = end - begin;
    uint32_t maxLeaf = uint32_t(std::clamp(options.maxLeafSize, 1, 65535));
    auto makeLeaf = [&] {
        nodes_[index].offset = begin;
        nodes_[index].count = uint16_t(count);
        return index;
    };
    if (count <= maxLeaf && (options.split != BvhSplit::Sah || count == 1)) return makeLeaf();

    Vec3 extent = centroidBox.diagonal();
    int axis = maxDimension(extent);
    uint32_t mid = begin;
    auto centroidOf = [&](uint32_t prim) { return centroids[prim][axis]; };

    if (extent[axis] > 0 && depth < kForceMedianDepth) {
        if (options.split == BvhSplit::Sah) {
            // Binned SAH: pick the bin boundary with the lowest cost, or make a leaf if that is
            // cheaper.
            Bounds3 binBox[kBins];
            uint32_t binCount[kBins] = {};
            float lo = centroidBox.lo[axis], scale = kBins / extent[axis];
            auto binOf = [&](uint32_t prim) {
                return std::min(kBins - 1, int((centroidOf(prim) - lo) * scale));
            };
            for (uint32_t i = begin; i < end; ++i) {
                int b = binOf(order_[i]);
                ++binCount[b];
                binBox[b].extend(boxes[order_[i]]);
            }
            float costs[kBins - 1];
            Bounds3 acc;
            uint32_t accCount = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.extend(binBox[b]);
                accCount += binCount[b];
                costs[b] = accCount * acc.surfaceArea();
            }
            acc = Bounds3();
            accCount = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.extend(binBox[b]);
                accCount += binCount[b];
                costs[b - 1] += accCount * acc.surfaceArea();
            }
            int best = int(std::min_element(costs, costs + kBins - 1) - costs);
            float area = box.surfaceArea();
            float splitCost = 1.0f + (area > 0 ? costs[best] / area : 0.0f);
            if (count <= maxLeaf && splitCost >= float(count)) return makeLeaf();
            mid = uint32_t(std::partition(order_.begin() + begin, order_.begin() + end,
                                          [&](uint32_t p) { return binOf(p) <= best; }) -
                           order_.begin());
        } else {
            float split;
            if (options.split == BvhSplit::Midpoint) {
                split = centroidBox.centroid()[axis];
            } else {
                double sum = 0;
                for (uint32_t i = begin; i < end; ++i) sum += centroidOf(order_[i]);
                split = float(sum / count);
            }
            mid = uint32_t(std::partition(order_.begin() + begin, order_.begin() + end,
                                          [&](uint32_t p) { return centroidOf(p) < split; }) -
                           order_.begin());
        }
    }
    if (mid == begin || mid == end) {
        // Every centroid on one side (or all equal): split the list in half instead of recursing
        // forever.
        if (count <= maxLeaf) return makeLeaf();
        mid = begin + count / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](uint32_t a, uint32_t b) { return centroidOf(a) < centroidOf(b); });
    }
    nodes_[index].axis = uint8_t(axis);
    buildRecursive(boxes, centroids, begin, mid, options, depth + 1);
    uint32_t second = buildRecursive(boxes, centroids, mid, end, options, depth + 1);
    nodes_[index].offset = second;
    nodes_[index].count = 0;
    return index;
}

BvhStatistics Bvh::statistics() const {
    BvhStatistics s;
    if (nodes_.empty()) return s;
    s.nodes = nodes_.size();
    float rootArea = nodes_[0].box.surfaceArea();
    struct Item {
        uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 1}};
    while (!stack.empty()) {
        Item it = stack.back();
        stack.pop_back();
        const BvhNode& n = nodes_[it.node];
        s.maxDepth = std::max<uint64_t>(s.maxDepth, it.depth);
        float rel = rootArea > 0 ? n.box.surfaceArea() / rootArea : 1.0f;
        if (n.count > 0) {
            ++s.leaves;
            s.sahCost += rel * n.count;
        } else {
            s.sahCost += rel;
            stack.push_back({it.node + 1, it.depth + 1});
            stack.push_back({n.offset, it.depth + 1});
        }
    }
    return s;
}

}  // namespace kiln
