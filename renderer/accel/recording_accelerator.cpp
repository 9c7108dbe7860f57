#include "renderer/accel/recording_accelerator.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>

namespace kiln {
namespace {

// 32 MiB of rays per chunk: enough calls per chunk that replaying one is real work, small enough
// that the chunks spread evenly over the threads.
constexpr size_t kChunkRays = size_t(1) << 20;

}  // namespace

void RecordingAccelerator::record(Call call, std::span<const Ray> rays, uint64_t hits) const {
    Log& log = logs_.local();
    log.hits += hits;
    if (log.chunks.empty() ||
        log.chunks.back().rays.size() + rays.size() > log.chunks.back().rays.capacity()) {
        Chunk& c = log.chunks.emplace_back();
        c.rays.reserve(std::max(kChunkRays, rays.size()));
    }
    Chunk& c = log.chunks.back();
    // Consecutive single-ray calls of one kind share a run.
    bool single = call == Call::Intersect1 || call == Call::Occluded1;
    if (single && !c.runs.empty() && c.runs.back().call == call)
        c.runs.back().count += uint32_t(rays.size());
    else
        c.runs.push_back({call, uint32_t(rays.size())});
    c.rays.insert(c.rays.end(), rays.begin(), rays.end());
}

bool RecordingAccelerator::intersect(const Ray& ray, Hit& hit) const {
    bool found = inner_.intersect(ray, hit);
    record(Call::Intersect1, std::span<const Ray>(&ray, 1), found ? 1 : 0);
    return found;
}

bool RecordingAccelerator::occluded(const Ray& ray) const {
    bool blocked = inner_.occluded(ray);
    record(Call::Occluded1, std::span<const Ray>(&ray, 1), blocked ? 1 : 0);
    return blocked;
}

void RecordingAccelerator::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    inner_.intersect(rays, hits);
    uint64_t found = 0;
    for (size_t i = 0; i < rays.size(); ++i) found += hits[i].valid();
    record(Call::IntersectBatch, rays, found);
}

void RecordingAccelerator::occluded(std::span<const Ray> rays, std::span<uint8_t> result) const {
    inner_.occluded(rays, result);
    uint64_t blocked = 0;
    for (size_t i = 0; i < rays.size(); ++i) blocked += result[i];
    record(Call::OccludedBatch, rays, blocked);
}

uint64_t RecordingAccelerator::recordedRays() const {
    uint64_t n = 0;
    for (const Log& log : logs_)
        for (const Chunk& c : log.chunks) n += c.rays.size();
    return n;
}

uint64_t RecordingAccelerator::recordedHits() const {
    uint64_t n = 0;
    for (const Log& log : logs_) n += log.hits;
    return n;
}

ReplayStats RecordingAccelerator::replay(int threads) const {
    std::vector<const Chunk*> chunks;
    for (const Log& log : logs_)
        for (const Chunk& c : log.chunks) chunks.push_back(&c);
    std::atomic<uint64_t> hits{0};
    struct PerKind {
        double seconds[4] = {0, 0, 0, 0};
        uint64_t rays[4] = {0, 0, 0, 0};
    };
    tbb::enumerable_thread_specific<PerKind> perKind;
    auto replayChunk = [&](const Chunk& chunk) {
        PerKind& pk = perKind.local();
        std::vector<Hit> hitBuffer;
        std::vector<uint8_t> blockedBuffer;
        uint64_t found = 0;
        size_t first = 0;
        for (const Run& run : chunk.runs) {
            std::span<const Ray> rays(chunk.rays.data() + first, run.count);
            first += run.count;
            auto t0 = std::chrono::steady_clock::now();
            switch (run.call) {
                case Call::Intersect1:
                    for (const Ray& r : rays) {
                        Hit h;
                        found += inner_.intersect(r, h);
                    }
                    break;
                case Call::Occluded1:
                    for (const Ray& r : rays) found += inner_.occluded(r);
                    break;
                case Call::IntersectBatch:
                    hitBuffer.resize(rays.size());
                    inner_.intersect(rays, std::span<Hit>(hitBuffer));
                    for (const Hit& h : hitBuffer) found += h.valid();
                    break;
                case Call::OccludedBatch:
                    blockedBuffer.resize(rays.size());
                    inner_.occluded(rays, std::span<uint8_t>(blockedBuffer));
                    for (uint8_t b : blockedBuffer) found += b;
                    break;
            }
            size_t k = size_t(run.call);
            pk.seconds[k] +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            pk.rays[k] += run.count;
        }
        hits += found;
    };
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks.size(), 1),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i != r.end(); ++i) replayChunk(*chunks[i]);
                          });
    });
    ReplayStats s;
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s.rays = recordedRays();
    s.hits = hits.load();
    for (const PerKind& pk : perKind)
        for (size_t k = 0; k < 4; ++k) {
            s.threadSeconds[k] += pk.seconds[k];
            s.raysOf[k] += pk.rays[k];
        }
    return s;
}

}  // namespace kiln
