// kiln farm submit and status as a wrangler drives them, before Slurm is asked: a bad --sbatch-arg
// and a missing sbatch are refused before anything is written; farm status --json fits
// docs/output.md's schema and farm status --help is help.
#include <gtest/gtest.h>

#include <fstream>

#include "json_schema.h"
#include "kiln_run.h"
#include "renderer/farm/farm_job.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string submitCommand(const fs::path& dir, const std::string& extra) {
    return "farm submit " + test::repo("scenes/cornell.dae") +
           " -r 16 12 -s 4 --shards 2 --by samples -d " + (dir / "job").string() + " -o " +
           (dir / "out/deep/frame").string() + " " + extra;
}

// What submit refuses without asking Slurm (what Slurm itself refuses, and that --sbatch-arg
// reaches it: FarmCluster.SbatchArgsReachSlurmAndARefusedSubmitLeavesNothing in test_farm.cpp).
TEST(FarmQueue, SubmitRefusesBeforeWritingAnything) {
    auto dir = test::scratchDir();
    // A value that is no option is refused before anything is written.
    test::CliRun bad = test::runKiln(submitCommand(dir / "b", "--sbatch-arg=account"));
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--sbatch-arg takes one sbatch option"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "b"));
    // No sbatch at all: refused before anything is written, exit 2.
    test::ScopedEnv path("PATH", (dir / "empty").string());
    test::CliRun r = test::runKiln(submitCommand(dir, ""));
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("sbatch is not on PATH"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "job"));
}

TEST(FarmQueue, StatusJsonFitsTheSchemaAndStatusHelpIsHelp) {
    auto dir = test::scratchDir();
    farm::FarmJob job = farm::planFarmJob(
        {{test::repo("scenes/cornell.dae"), {"-r", "16", "12", "-s", "4"}, (dir / "f").string()}},
        farm::ShardBy::Samples, 2, (dir / "job").string());
    fs::create_directories(job.dir);
    farm::writeManifest(job);  // planned, never submitted: both shards pending
    test::CliRun r = test::runKiln("farm status " + job.dir + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    json status = json::parse(r.out);
    test::JsonSchema schema = test::readJsonSchema();
    EXPECT_EQ(test::schemaErrors(schema, "farm-status", status), "");
    EXPECT_EQ(status["status"], "done");
    EXPECT_EQ(status["counts"]["pending"], 2);
    ASSERT_EQ(status["shards"].size(), 2u);
    for (const json& shard : status["shards"]) {
        EXPECT_EQ(test::schemaErrors(schema, "farm-shard", shard), "");
        EXPECT_EQ(shard["state"], "pending");
    }
    test::CliRun help = test::runKiln("farm status --help");
    EXPECT_EQ(help.code, 0) << help.err;
    EXPECT_EQ(help.out.rfind("usage: kiln farm status DIR", 0), 0u) << help.out;
    EXPECT_NE(help.out.find("--json"), std::string::npos);
}

}  // namespace
}  // namespace kiln
