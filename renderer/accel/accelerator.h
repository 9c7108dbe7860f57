// One traversal interface for both accelerators: closest hit and occlusion, single rays and
// batches.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "renderer/core/enum_names.h"
#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

struct AcceleratorStats {
    double buildSeconds = 0;
    uint64_t memoryBytes = 0;  // acceleration structure only
    std::string description;
};

class Accelerator {
  public:
    virtual ~Accelerator() = default;
    // Closest hit in [ray.tMin, ray.tMax]; false (and hit untouched) when nothing is hit.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    // Any hit in [ray.tMin, ray.tMax].
    virtual bool occluded(const Ray& ray) const = 0;
    virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
        for (size_t i = 0; i < rays.size(); ++i) {
            hits[i] = Hit{};
            intersect(rays[i], hits[i]);
        }
    }
    virtual void occluded(std::span<const Ray> rays, std::span<uint8_t> result) const {
        for (size_t i = 0; i < rays.size(); ++i) result[i] = occluded(rays[i]) ? 1 : 0;
    }
    virtual const AcceleratorStats& stats() const = 0;
};

enum class AcceleratorKind { Embree, Reference, BruteForce };

struct EmbreeOptions {
    enum class Quality { Low, Medium, High } quality = Quality::Medium;
    bool robust =
        true;  // RTC_SCENE_FLAG_ROBUST: watertight shared edges (see docs/accelerators.md)
    bool compact = false;  // RTC_SCENE_FLAG_COMPACT: smaller BVH, a little slower
    // Triangles as user geometry running kiln's watertight test (shapes.h) inside Embree's BVH:
    // closes Embree's float test's cracks at shared vertices, at a measured cost
    // (docs/robustness.md).
    bool watertight = false;
    int threads = 0;  // 0 = all

    bool operator==(const EmbreeOptions&) const = default;
};

enum class BvhSplit { Sah, MeanCentroid, Midpoint };

template <>
struct EnumNames<AcceleratorKind> {
    static constexpr std::pair<AcceleratorKind, const char*> table[] = {
        {AcceleratorKind::Embree, "embree"},
        {AcceleratorKind::Reference, "reference"},
        {AcceleratorKind::BruteForce, "brute"}};
};
template <>
struct EnumNames<EmbreeOptions::Quality> {
    static constexpr std::pair<EmbreeOptions::Quality, const char*> table[] = {
        {EmbreeOptions::Quality::Low, "low"},
        {EmbreeOptions::Quality::Medium, "medium"},
        {EmbreeOptions::Quality::High, "high"}};
};
template <>
struct EnumNames<BvhSplit> {
    static constexpr std::pair<BvhSplit, const char*> table[] = {
        {BvhSplit::Sah, "sah"}, {BvhSplit::MeanCentroid, "mean"}, {BvhSplit::Midpoint, "midpoint"}};
};

struct ReferenceBvhOptions {
    BvhSplit split = BvhSplit::Sah;
    int maxLeafSize = 4;

    bool operator==(const ReferenceBvhOptions&) const = default;
};

std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene,
                                                   const EmbreeOptions& options = {});
std::unique_ptr<Accelerator> makeReferenceAccelerator(const Scene& scene,
                                                      const ReferenceBvhOptions& options = {});

}  // namespace kiln
