// Every JSON document and event kiln render writes for a job queue, validated against the schema
// table in docs/output.md: the result of a finished, a time-limited, a failed-to-write and a
// refused render, and every stderr line of a --progress json render, whose stages all appear.
#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "json_schema.h"
#include "kiln_run.h"

namespace kiln {
namespace {

using nlohmann::json;

// Each stderr line is one JSON event; each is checked against its event's schema. Returns them.
std::vector<json> checkedEvents(const test::JsonSchema& schema, const std::string& err,
                                std::set<std::string>& seen) {
    std::vector<json> events;
    std::istringstream lines(err);
    for (std::string line; std::getline(lines, line);) {
        json e = json::parse(line);
        std::string event = e.value("event", "");
        seen.insert(event);
        EXPECT_EQ(test::schemaErrors(schema, event, e), "") << line;
        events.push_back(e);
    }
    return events;
}

void checkResult(const test::JsonSchema& schema, const std::string& document, const json& r,
                 std::set<std::string>& seen) {
    seen.insert(document);
    EXPECT_EQ(test::schemaErrors(schema, document, r), "") << r.dump(2);
    for (const json& n : r["not_written"]) {
        seen.insert("not-written");
        EXPECT_EQ(test::schemaErrors(schema, "not-written", n), "") << n.dump();
    }
}

bool isBatchDocument(const std::string& document) {
    return document == "task" || document.rfind("batch-", 0) == 0 ||
           document.rfind("farm-", 0) == 0;
}

TEST(JsonSchema, EveryDocumentAndEventOfARenderFitsTheDocumentedSchema) {
    test::JsonSchema schema = test::readJsonSchema();
    ASSERT_GE(schema.size(), 7u);
    auto dir = test::scratchDir();
    std::string scene = test::repo("scenes/cornell.dae");
    std::set<std::string> seen;

    // A guided render (the Cornell box's plan guides it) of a few seconds: every stage, progress
    // lines (one a second) and messages.
    test::CliRun done =
        test::runKiln("render " + scene + " -r 96 72 -s 1024 --json --progress json -o " +
                      (dir / "done").string());
    ASSERT_EQ(done.code, 0) << done.err;
    json result = json::parse(done.out);
    checkResult(schema, "render-result", result, seen);
    EXPECT_EQ(result["status"], "done");
    EXPECT_EQ(result["exit_code"], 0);
    EXPECT_EQ(result["outputs"]["exr"], (dir / "done.exr").string());
    EXPECT_TRUE(result["not_written"].empty());
    std::vector<std::string> stages;
    for (const json& e : checkedEvents(schema, done.err, seen))
        if (e["event"] == "stage" && e["state"] == "start") stages.push_back(e["stage"]);
    EXPECT_EQ(stages, (std::vector<std::string>{"load", "build", "plan", "guide_training", "render",
                                                "write"}));

    // A time limit: its status, and the checkpoint among the outputs.
    test::CliRun limited =
        test::runKiln("render " + scene + " -r 32 24 -s 100000 --time-limit 0.01 --json -q -o " +
                      (dir / "limited").string());
    ASSERT_EQ(limited.code, 3) << limited.err;
    json l = json::parse(limited.out);
    checkResult(schema, "render-result", l, seen);
    EXPECT_EQ(l["status"], "time-limit");
    EXPECT_EQ(l["time_limit_reached"], true);
    EXPECT_EQ(l["outputs"]["checkpoint"], (dir / "limited.ckpt").string());

    // A usage error and an output whose name is a directory: one failure result, JSON lines only.
    test::CliRun bogus = test::runKiln("render " + scene + " --json --aov bogus");
    EXPECT_EQ(bogus.code, 2);
    json b = json::parse(bogus.out);
    checkResult(schema, "failure-result", b, seen);
    EXPECT_EQ(b["status"], "failed");
    EXPECT_EQ(b["exit_code"], 2);
    EXPECT_NE(b["error"].get<std::string>().find("bogus"), std::string::npos);
    checkedEvents(schema, bogus.err, seen);
    std::filesystem::create_directories(dir / "taken.exr");
    test::CliRun taken =
        test::runKiln("render " + scene + " --json -o " + (dir / "taken.exr").string());
    EXPECT_EQ(taken.code, 2) << taken.err;
    json t = json::parse(taken.out);
    checkResult(schema, "failure-result", t, seen);
    ASSERT_EQ(t["not_written"].size(), 1u) << taken.out;
    EXPECT_EQ(t["not_written"][0]["path"], (dir / "taken.exr").string());
    checkedEvents(schema, taken.err, seen);

    // Every document of kiln render the table lists was met (the batch's: BatchQueue.*).
    for (const auto& [document, fields] : schema)
        EXPECT_TRUE(isBatchDocument(document) || seen.count(document)) << document;
}

// A write that fails after the render (the preview's name becomes a directory while the render is
// stopped): exit 1, status failed, the EXR among the outputs and the preview in not_written.
TEST(JsonSchema, AFailedWriteIsListedAsNotWritten) {
    auto dir = test::scratchDir();
    std::string out = (dir / "late").string();
    std::string script = std::string(KILN_BINARY) + " render " + test::repo("scenes/cornell.dae") +
                         " -r 96 72 -s 32 --json --progress json -o " + out + " >" + out +
                         ".json 2>" + out + ".err & pid=$!; until grep -q '\"stage\":\"render\"' " +
                         out + ".err; do sleep 0.005; done; kill -STOP $pid; mkdir " + out +
                         ".png; kill -CONT $pid; wait $pid";
    test::CliRun r = test::runProgram("sh", "-c " + test::shellQuoted(script));
    EXPECT_EQ(r.code, 1) << r.err;
    std::ifstream in(out + ".json");
    json result = json::parse(in);
    EXPECT_EQ(test::schemaErrors(test::readJsonSchema(), "render-result", result), "");
    EXPECT_EQ(result["status"], "failed");
    EXPECT_EQ(result["exit_code"], 1);
    EXPECT_EQ(result["outputs"]["exr"], out + ".exr");
    EXPECT_FALSE(result["outputs"].contains("preview"));
    ASSERT_EQ(result["not_written"].size(), 1u) << result.dump(2);
    EXPECT_EQ(result["not_written"][0]["kind"], "preview");
    EXPECT_EQ(result["not_written"][0]["path"], out + ".png");
    EXPECT_FALSE(result["not_written"][0]["error"].get<std::string>().empty());
}

}  // namespace
}  // namespace kiln
