#include "renderer/guide_training.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace kiln {
namespace {

// The training's random numbers: another stream than every render seed's.
constexpr uint64_t kTrainingSeedSalt = 0x67756964655f7472ull;
constexpr size_t kBatchPhotons = 4096;

}  // namespace

std::string GuideTraining::describe(const GuideField& field) {
    const GuideField::Stats& s = field.stats();
    return fmt::format("on: {} photons, {} landed caustics, {} regions", kPhotons, s.records,
                       s.leaves);
}

std::shared_ptr<const GuideField> trainGuide(const PathIntegrator& integrator,
                                             const RenderSettings& settings) {
    const uint64_t seed = settings.seed ^ kTrainingSeedSalt;
    const size_t batches = GuideTraining::kPhotons / kBatchPhotons;
    std::vector<std::vector<GuideRecord>> perBatch(batches);
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(size_t(0), batches, [&](size_t b) {
            integrator.traceCausticPhotons(b * kBatchPhotons, kBatchPhotons, seed, perBatch[b]);
        });
    });
    size_t count = 0;
    for (const auto& r : perBatch) count += r.size();
    std::vector<GuideRecord> records;
    records.reserve(count);
    for (const auto& r : perBatch) records.insert(records.end(), r.begin(), r.end());
    return std::make_shared<const GuideField>(std::move(records), GuideTraining::kLeafRecords);
}

}  // namespace kiln
