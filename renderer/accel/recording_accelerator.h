// The traversal floor of a render: an accelerator that passes every call through to another one
// and records it (the rays, and whether they went one at a time or as a batch), so the same calls
// can be traced again with nothing else running. Render time minus replay time is what shading,
// sampling and the film cost on top of Embree.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <vector>

#include "renderer/accel/accelerator.h"

namespace kiln {

// How a traversal call was made; indexes ReplayStats' per-kind arrays.
enum class TraversalCall : uint8_t { Intersect1, IntersectBatch, Occluded1, OccludedBatch };

struct ReplayStats {
    double seconds = 0;
    uint64_t rays = 0;
    uint64_t hits = 0;  // closest hits found plus occluded shadow rays
    // Per kind of call (TraversalCall), summed over threads.
    double threadSeconds[4] = {0, 0, 0, 0};
    uint64_t raysOf[4] = {0, 0, 0, 0};
};

class RecordingAccelerator final : public Accelerator {
  public:
    explicit RecordingAccelerator(const Accelerator& inner) : inner_(inner) {}

    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override;
    void occluded(std::span<const Ray> rays, std::span<uint8_t> result) const override;
    const AcceleratorStats& stats() const override { return inner_.stats(); }

    // What the recorded calls returned while recording.
    uint64_t recordedRays() const;
    uint64_t recordedHits() const;
    // Traces every recorded call again through the inner accelerator, each call as it was made
    // (single rays one at a time, batches as batches), on `threads` threads (0 = all).
    ReplayStats replay(int threads) const;

  private:
    using Call = TraversalCall;
    struct Run {
        Call call;
        uint32_t count;  // rays
    };
    // Rays in chunks of fixed capacity (no reallocation of gigabytes), a run never split between
    // chunks; the chunks are the replay's unit of parallel work.
    struct Chunk {
        std::vector<Run> runs;
        std::vector<Ray> rays;
    };
    struct Log {
        std::vector<Chunk> chunks;
        uint64_t hits = 0;
    };

    void record(Call call, std::span<const Ray> rays, uint64_t hits) const;

    const Accelerator& inner_;
    mutable tbb::enumerable_thread_specific<Log> logs_;
};

}  // namespace kiln
