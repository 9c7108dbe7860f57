#include "renderer/shard_merge.h"

#include <algorithm>
#include <set>

#include "renderer/core/memory.h"

namespace kiln {
namespace {

struct Shard {
    std::string path;
    CheckpointInfo info;
    int x1() const { return info.originX + info.width; }
    int y1() const { return info.originY + info.height; }
};

std::string cellText(int x0, int x1, int y0, int y1) {
    return "pixels x " + std::to_string(x0) + ".." + std::to_string(x1 - 1) + ", y " +
           std::to_string(y0) + ".." + std::to_string(y1 - 1);
}

void checkSameRender(const std::vector<Shard>& shards) {
    const Shard& first = shards.front();
    for (const Shard& s : shards) {
        std::string diff =
            fingerprintDifference(s.info.fingerprint, first.info.fingerprint, s.path);
        if (!diff.empty())
            throw CheckpointError(s.path + ": another render than " + first.path + ": " + diff +
                                  " (in " + first.path + ")");
        if (!s.info.complete)
            throw CheckpointError(s.path +
                                  ": shard is unfinished (finish it with kiln render "
                                  "... --resume, then merge)");
    }
}

// Every pixel of the shards' bounding box must hold samples [0, N) exactly once, N the same
// everywhere. Checked per cell of the grid the shard edges cut: few cells for a farm's grid.
int checkCoverage(const std::vector<Shard>& shards, int& x0, int& y0, int& x1, int& y1) {
    std::set<int> xs, ys;
    for (const Shard& s : shards) {
        xs.insert(s.info.originX), xs.insert(s.x1());
        ys.insert(s.info.originY), ys.insert(s.y1());
    }
    x0 = *xs.begin(), x1 = *xs.rbegin(), y0 = *ys.begin(), y1 = *ys.rbegin();
    int total = -1;
    std::vector<const Shard*> here;
    for (auto yi = ys.begin(); std::next(yi) != ys.end(); ++yi)
        for (auto xi = xs.begin(); std::next(xi) != xs.end(); ++xi) {
            int cx = *xi, cy = *yi;
            std::string cell = cellText(cx, *std::next(xi), cy, *std::next(yi));
            here.clear();
            for (const Shard& s : shards)
                if (s.info.originX <= cx && cx < s.x1() && s.info.originY <= cy && cy < s.y1())
                    here.push_back(&s);
            if (here.empty()) throw CheckpointError(cell + " are in no shard");
            std::sort(here.begin(), here.end(), [](const Shard* a, const Shard* b) {
                return a->info.sampleStart < b->info.sampleStart;
            });
            int reached = 0;
            const Shard* last = nullptr;
            for (const Shard* s : here) {
                if (s->info.sampleStart < reached)
                    throw CheckpointError(s->path + " and " + last->path + " overlap: both hold " +
                                          "sample " + std::to_string(s->info.sampleStart) + " of " +
                                          cell);
                if (s->info.sampleStart > reached)
                    throw CheckpointError("samples " + std::to_string(reached) + ".." +
                                          std::to_string(s->info.sampleStart - 1) + " of " + cell +
                                          " are in no shard");
                reached = s->info.sampleEnd, last = s;
            }
            if (total >= 0 && reached != total)
                throw CheckpointError(cell + " reach sample " + std::to_string(reached) +
                                      ", other pixels " + std::to_string(total) +
                                      " (a sample-range shard is missing)");
            total = reached;
        }
    return total;
}

// The merged film in memory (shards are streamed into it).
void checkMemory(const CheckpointInfo& first, uint64_t pixels) {
    uint64_t perPixel = 0;
    for (const FilmBuffer& b : Film(1, 1, first.aovs).buffers()) perPixel += b.bytes(1);
    uint64_t need = pixels * perPixel, available = availableMemoryBytes();
    if (need > available)
        throw CheckpointError("merging needs " + std::to_string(need >> 20) + " MiB, " +
                              std::to_string(available >> 20) + " MiB available");
}

}  // namespace

MergedRender mergeShards(const std::vector<std::string>& paths) {
    if (paths.empty()) throw CheckpointError("no shards to merge");
    std::vector<Shard> shards;
    for (const std::string& p : paths) shards.push_back({p, readCheckpointInfo(p)});
    checkSameRender(shards);
    int x0, y0, x1, y1;
    int spp = checkCoverage(shards, x0, y0, x1, y1);
    // Earliest samples first: a pixel's first-sample values (ids) come from sample 0's shard.
    std::stable_sort(shards.begin(), shards.end(), [](const Shard& a, const Shard& b) {
        return a.info.sampleStart < b.info.sampleStart;
    });
    const CheckpointInfo& first = shards.front().info;
    checkMemory(first, uint64_t(x1 - x0) * uint64_t(y1 - y0));
    MergedRender out{Film(x1 - x0, y1 - y0, first.aovs), first};
    out.film.setRegion(x0, y0, first.fullWidth, first.fullHeight);
    out.film.setScaleExponent(first.filmScaleExponent);
    out.info.originX = x0, out.info.originY = y0;
    out.info.width = x1 - x0, out.info.height = y1 - y0;
    out.info.sampleStart = 0, out.info.sampleEnd = spp;
    out.info.rays = out.info.nonFiniteSamples = 0;
    out.info.seconds = 0;
    for (const Shard& s : shards) {
        CheckpointInfo info;
        mergeCheckpoint(s.path, out.film, info);
        out.info.rays += info.rays;
        out.info.nonFiniteSamples += info.nonFiniteSamples;
        out.info.seconds += info.seconds;
    }
    Metadata& m = out.info.metadata;
    m["spp"] = std::to_string(spp);
    m["sample_range"] = "0 " + std::to_string(spp);
    m["mean_spp"] = std::to_string(double(out.film.totalSamples()) /
                                   (double(out.film.width()) * out.film.height()));
    m["rays"] = std::to_string(out.info.rays);
    m["render_seconds"] = std::to_string(out.info.seconds);
    m["nonfinite_samples"] = std::to_string(out.info.nonFiniteSamples);
    m["interrupted"] = "no";
    m["merged_shards"] = std::to_string(shards.size());
    return out;
}

}  // namespace kiln
