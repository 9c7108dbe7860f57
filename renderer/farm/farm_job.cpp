#include "renderer/farm/farm_job.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "renderer/render_loop.h"

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The samples per pixel a render's options ask for (the last -s/--spp wins, as in the parser).
int sppOf(const RenderTask& task) {
    int spp = RenderSettings{}.spp;
    for (size_t i = 0; i + 1 < task.args.size(); ++i)
        if (task.args[i] == "-s" || task.args[i] == "--spp")
            spp = std::atoi(task.args[i + 1].c_str());
    return spp;
}

std::string fraction(int i, int n) { return fmt::format("{:.17g}", double(i) / n); }

// Part `part` of `parts` of one render: its own output in DIR/shards.
RenderTask partOf(const RenderTask& task, ShardBy by, int part, int parts, size_t taskIndex,
                  const std::string& dir) {
    RenderTask p = task;
    std::string name = fmt::format("shards/r{:04}_p{:03}", taskIndex, part);
    p.output = (fs::path(dir) / name).string();
    if (by == ShardBy::Samples) {
        int spp = sppOf(task);
        p.args.insert(p.args.end(), {"--sample-range", std::to_string(int64_t(spp) * part / parts),
                                     std::to_string(int64_t(spp) * (part + 1) / parts)});
    } else {
        p.args.insert(p.args.end(),
                      {"--crop", "0", "1", fraction(part, parts), fraction(part + 1, parts)});
    }
    return p;
}

json taskJson(const RenderTask& t) {
    return {{"scene", t.scene}, {"args", t.args}, {"output", t.output}};
}

RenderTask taskFrom(const json& j) {
    return {j.at("scene").get<std::string>(), j.at("args").get<std::vector<std::string>>(),
            j.at("output").get<std::string>()};
}

}  // namespace

ShardBy parseShardBy(const std::string& text) {
    if (std::optional<ShardBy> by = parseEnum<ShardBy>(text)) return *by;
    throw FarmInputError(fmt::format("--by takes {}, got '{}'", enumChoices<ShardBy>(), text));
}

const char* shardByName(ShardBy by) { return toString(by); }

FarmJob planFarmJob(const std::vector<RenderTask>& tasks, ShardBy by, int shards,
                    const std::string& dir, int framesPerTask) {
    FarmJob job;
    job.dir = fs::absolute(dir).lexically_normal().string();
    job.by = by;
    if (by == ShardBy::Frames) {
        const size_t chunk = size_t(std::max(framesPerTask, 0));
        const size_t n = chunk ? (tasks.size() + chunk - 1) / chunk
                               : std::min(size_t(std::max(shards, 1)), tasks.size());
        job.shards.resize(n);
        // Contiguous runs of frames: chunks of framesPerTask, or the first runs one longer when
        // the renders do not divide evenly into `shards`.
        for (size_t t = 0; t < tasks.size(); ++t)
            job.shards[chunk ? t / chunk : t * n / tasks.size()].tasks.push_back(tasks[t]);
        return job;
    }
    for (size_t t = 0; t < tasks.size(); ++t) {
        if (by == ShardBy::Samples && sppOf(tasks[t]) < shards)
            throw FarmInputError(tasks[t].output + ": " + std::to_string(sppOf(tasks[t])) +
                                 " samples per pixel cannot make " + std::to_string(shards) +
                                 " sample shards (raise -s or lower --shards)");
        Merge merge{tasks[t].output, {}};
        for (int p = 0; p < shards; ++p) {
            RenderTask part = partOf(tasks[t], by, p, shards, t, job.dir);
            merge.inputs.push_back(part.output);
            job.shards.push_back({{part}});
        }
        job.merges.push_back(merge);
    }
    return job;
}

std::vector<std::string> mergeCommand(const Merge& merge) {
    std::vector<std::string> cmd{"merge"};
    for (const std::string& in : merge.inputs) cmd.push_back(in + ".ckpt");
    cmd.insert(cmd.end(), {"-o", merge.output});
    return cmd;
}

std::string manifestPath(const std::string& dir) {
    return (fs::path(dir) / "manifest.json").string();
}

void writeManifest(const FarmJob& job) {
    json doc = {{"dir", job.dir},
                {"kiln", job.kiln},
                {"by", shardByName(job.by)},
                {"checkpoint_every", job.checkpointSeconds},
                {"keep_checkpoints", job.keepCheckpoints},
                {"sbatch_options", job.sbatchOptions},
                {"shards", json::array()},
                {"merges", json::array()},
                {"submissions", json::array()}};
    for (const Shard& s : job.shards) {
        json tasks = json::array();
        for (const RenderTask& t : s.tasks) tasks.push_back(taskJson(t));
        doc["shards"].push_back({{"renders", tasks}});
    }
    for (const Merge& m : job.merges)
        doc["merges"].push_back({{"output", m.output}, {"inputs", m.inputs}});
    for (const Submission& s : job.submissions)
        doc["submissions"].push_back(
            {{"array_job", s.arrayJob}, {"merge_job", s.mergeJob}, {"shards", s.shards}});
    writeFileAtomically(manifestPath(job.dir), doc.dump(2) + "\n");
}

FarmJob readManifest(const std::string& dir) {
    std::string path = manifestPath(dir);
    json doc = json::parse(readFileText(path), nullptr, false);
    if (doc.is_discarded()) throw FarmInputError(path + ": is not valid JSON");
    try {
        FarmJob job;
        job.dir = doc.at("dir").get<std::string>();
        job.kiln = doc.at("kiln").get<std::string>();
        job.by = parseShardBy(doc.at("by").get<std::string>());
        job.checkpointSeconds = doc.at("checkpoint_every").get<int>();
        job.keepCheckpoints = doc.at("keep_checkpoints").get<bool>();
        job.sbatchOptions = doc.at("sbatch_options").get<std::vector<std::string>>();
        for (const json& s : doc.at("shards")) {
            Shard shard;
            for (const json& t : s.at("renders")) shard.tasks.push_back(taskFrom(t));
            job.shards.push_back(shard);
        }
        for (const json& m : doc.at("merges"))
            job.merges.push_back({m.at("output").get<std::string>(),
                                  m.at("inputs").get<std::vector<std::string>>()});
        for (const json& s : doc.at("submissions"))
            job.submissions.push_back({s.at("array_job").get<long>(), s.at("merge_job").get<long>(),
                                       s.at("shards").get<std::vector<int>>()});
        return job;
    } catch (const json::exception& e) {
        throw FarmInputError(path + ": not a kiln farm manifest (" + e.what() + ")");
    }
}

}  // namespace kiln::farm
