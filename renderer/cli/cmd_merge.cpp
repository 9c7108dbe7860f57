// kiln merge: shard checkpoints (kiln render --sample-range / --crop) into the final EXR + PNG.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "color/image_output.h"
#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/output_check.h"
#include "renderer/core/log.h"
#include "renderer/denoise_film.h"
#include "renderer/shard_merge.h"

namespace kiln {
namespace {

ExrOptions exrOptionsOf(const Metadata& meta) {
    ExrOptions exr;
    auto it = meta.find("exr_storage");
    if (it == meta.end()) return exr;
    exr.half = it->second.rfind("half", 0) == 0;
    std::string compression = it->second.substr(it->second.find(' ') + 1);
    std::optional<ExrCompression> known = parseEnum<ExrCompression>(compression);
    if (!known)
        throw UsageError("the shards name an unknown EXR compression '" + compression + "'");
    exr.compression = *known;
    return exr;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string metaOr(const Metadata& meta, const char* key, const char* fallback) {
    auto it = meta.find(key);
    return it == meta.end() ? fallback : it->second;
}

}  // namespace

int runMerge(const std::vector<std::string>& args) {
    std::string output;
    ArgParser parser("merge", "SHARD.ckpt... -o OUT   (writes OUT.exr and OUT.png)");
    parser.option("output", "o", 1, "OUT", "output base name: OUT.exr and OUT.png",
                  [&output](const std::vector<std::string>& v) { output = v[0]; });
    std::vector<std::string> shards = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        std::fputs(
            "\nThe shards (sample ranges, crop regions, or both) must be finished renders "
            "of one scene and settings that cover every pixel's samples exactly once; the "
            "result equals the single-process render bit for bit. Exit status: 0 done, 1 "
            "a write failed, 2 bad, overlapping, missing or foreign shards.\n",
            stdout);
        return 0;
    }
    if (shards.empty()) throw UsageError("needs at least one SHARD.ckpt");
    if (output.empty()) throw UsageError("needs -o OUT");
    std::string base = output;
    if (std::filesystem::path(base).extension() == ".exr")
        base = std::filesystem::path(base).replace_extension("").string();
    checkOutputBase(base);
    checkOutputFiles({base + ".exr", base + ".png"});
    auto t0 = std::chrono::steady_clock::now();
    MergedRender merged = [&] {
        try {
            return mergeShards(shards);
        } catch (const CheckpointError& e) {
            throw UsageError(e.what());
        }
    }();
    double mergeSeconds = secondsSince(t0);
    uint64_t shardBytes = 0;
    for (const std::string& s : shards) shardBytes += std::filesystem::file_size(s);
    auto t1 = std::chrono::steady_clock::now();
    Metadata meta = merged.info.metadata;
    ExrOptions exr = exrOptionsOf(meta);
    // Shards rendered with --denoise carry the half-buffers: the merged frame is denoised too.
    if (merged.film.hasHalves()) denoiseForOutputs(merged.film, 0, exr, meta);
    writeExr(base + ".exr", merged.film, meta, exr);
    writePreview(base + ".png", merged.film, metaOr(meta, "display", "sRGB"),
                 metaOr(meta, "view", "Standard"), 0, metaOr(meta, "look", ""), exr.denoised.get());
    logInfo(
        "merged {} shards ({} samples, {:.1f} MiB) -> {}.exr, {}.png; read and combine {:.3f}s "
        "({:.0f} MiB/s), write {:.3f}s",
        shards.size(), merged.film.totalSamples(), double(shardBytes) / (1 << 20), base, base,
        mergeSeconds, double(shardBytes) / (1 << 20) / std::max(mergeSeconds, 1e-9),
        secondsSince(t1));
    return 0;
}

}  // namespace kiln
