// kiln batch as a wrangler drives it: --dry-run checks and plans every render and renders none;
// --progress json makes all of stderr JSON (task events with the batch's ETA, the renders' own
// events), each line and the --json result valid against docs/output.md's schema; the per-task
// lines obey --log-level.
#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "json_schema.h"
#include "kiln_run.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string threeFrameJob(const fs::path& dir, const std::string& settings = "") {
    return test::writeFile(dir / "job.json",
                           R"({"output": "out/{camera}_{frame}{settings}", "scenes": [")" +
                               test::repo("scenes/cornell.dae") +
                               R"("], "args": ["-r", 16, 12, "-s", 2], )" + settings +
                               R"("cameras": [{"name": "orbit", "turntable": 3}]})");
}

void expectFits(const test::JsonSchema& schema, const std::string& document, const json& doc,
                std::set<std::string>& seen) {
    seen.insert(document);
    EXPECT_EQ(test::schemaErrors(schema, document, doc), "") << doc.dump();
}

TEST(BatchQueue, DryRunChecksEveryRenderAndRendersNone) {
    test::JsonSchema schema = test::readJsonSchema();
    std::set<std::string> seen;
    auto dir = test::scratchDir();
    std::string job = threeFrameJob(dir);
    test::CliRun r = test::runKiln("batch " + job + " --dry-run --json");
    ASSERT_EQ(r.code, 0) << r.err;
    json plan = json::parse(r.out);
    expectFits(schema, "batch-dry-run", plan, seen);
    ASSERT_EQ(plan["renders"].size(), 3u);
    for (const json& render : plan["renders"]) {
        expectFits(schema, "batch-dry-run-render", render, seen);
        EXPECT_EQ(render["state"], "render");
    }
    EXPECT_FALSE(fs::exists(dir / "out")) << "a dry run rendered";
    // A bad value in one settings entry: one error naming the job file and the entry, exit 2.
    job = threeFrameJob(dir, R"("settings": [{"name": "a", "args": ["-s", 4]}, )"
                             R"({"name": "b", "args": ["--spp", 0]}], )");
    r = test::runKiln("batch " + job + " --dry-run");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find(job + ": settings[1]: 'args': "), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(BatchQueue, ProgressJsonThroughTheBatchWithItsEta) {
    test::JsonSchema schema = test::readJsonSchema();
    std::set<std::string> seen;
    auto dir = test::scratchDir();
    std::string job = threeFrameJob(dir);
    test::CliRun r = test::runKiln("batch " + job + " --progress json --json");
    ASSERT_EQ(r.code, 0) << r.err;
    json result = json::parse(r.out);
    expectFits(schema, "batch-result", result, seen);
    EXPECT_EQ(result["status"], "done");
    for (const json& render : result["renders"]) expectFits(schema, "batch-render", render, seen);
    std::istringstream lines(r.err);
    std::vector<json> ended;
    std::set<std::string> stages;
    for (std::string line; std::getline(lines, line);) {
        json e = json::parse(line);  // every line of stderr is JSON
        expectFits(schema, e["event"], e, seen);
        if (e["event"] == "task" && e["state"] == "rendered") ended.push_back(e);
        if (e["event"] == "stage") stages.insert(e["stage"].get<std::string>());
    }
    ASSERT_EQ(ended.size(), 3u) << r.err;
    // The ETA after each render: the mean time so far times the renders left.
    double total = 0;
    for (size_t i = 0; i < 3; ++i) {
        total += ended[i]["seconds"].get<double>();
        EXPECT_NEAR(ended[i]["eta_seconds"].get<double>(), total / double(i + 1) * double(2 - i),
                    1e-9);
    }
    EXPECT_EQ(stages.size(), 6u) << "the renders' own stage events pass through";
    for (const auto& [document, fields] : schema) {
        const bool batchRun = document == "task" || (document.rfind("batch-", 0) == 0 &&
                                                     document.find("dry-run") == std::string::npos);
        EXPECT_TRUE(!batchRun || seen.count(document)) << document;
    }
}

TEST(BatchQueue, TaskLinesObeyTheLogLevel) {
    auto dir = test::scratchDir();
    std::string job = threeFrameJob(dir);
    test::CliRun text = test::runKiln("batch " + job + " -q");
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.err.find("kiln: [1/3] "), std::string::npos) << text.err;
    EXPECT_NE(text.err.find("batch ETA"), std::string::npos) << text.err;
    EXPECT_EQ(text.err.find("Mrays/s"), std::string::npos) << "the renders' summaries at info";
    fs::remove_all(dir / "out");
    test::CliRun quiet = test::runKiln("batch " + job + " -q --log-level error");
    ASSERT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "");
    EXPECT_TRUE(fs::exists(dir / "out/orbit_2.exr"));
}

}  // namespace
}  // namespace kiln
