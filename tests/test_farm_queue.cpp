// kiln farm submit and status as a wrangler drives them, with a stand-in sbatch on PATH (a shell
// script that records the job script it is given and answers as sbatch does, or refuses as sbatch
// does): options given with --sbatch-arg reach both job scripts; a submit that fails leaves no
// folder behind; a missing sbatch is refused before anything is written; farm status --json fits
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

// A folder holding an executable `sbatch` that either copies its last argument (the job script)
// to DIR/submitted-N.sbatch and prints a job id, or prints Slurm's error and exits 1.
std::string sbatchStandIn(const fs::path& dir, bool accepts) {
    fs::path bin = dir / (accepts ? "accepting" : "refusing");
    fs::create_directories(bin);
    std::string body = accepts
                           ? "n=$(ls " + dir.string() +
                                 " | grep -c submitted); for a; do last=$a; done; cp \"$last\" " +
                                 dir.string() + "/submitted-$n.sbatch; echo $((42 + n))\n"
                           : "echo 'sbatch: error: Invalid account or account/partition "
                             "combination specified' >&2; exit 1\n";
    test::writeFile(bin / "sbatch", "#!/bin/sh\n" + body);
    fs::permissions(bin / "sbatch", fs::perms::owner_all);
    return bin.string();
}

std::string submitCommand(const fs::path& dir, const std::string& extra) {
    return "farm submit " + test::repo("scenes/cornell.dae") +
           " -r 16 12 -s 4 --shards 2 --by samples -d " + (dir / "job").string() + " -o " +
           (dir / "out/deep/frame").string() + " " + extra;
}

TEST(FarmQueue, SbatchArgReachesBothJobScripts) {
    auto dir = test::scratchDir();
    test::ScopedEnv path("PATH", sbatchStandIn(dir, true) + ":" + std::getenv("PATH"));
    test::CliRun r = test::runKiln(submitCommand(
        dir, "--sbatch-arg=--account=fx --sbatch-arg=--qos=high --sbatch-arg=--constraint=avx2"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "42\n");
    for (const char* script : {"submitted-0.sbatch", "submitted-1.sbatch"}) {
        std::string text = farm::readFileText((dir / script).string());
        for (const char* line :
             {"#SBATCH --account=fx\n", "#SBATCH --qos=high\n", "#SBATCH --constraint=avx2\n"})
            EXPECT_NE(text.find(line), std::string::npos) << script << ":\n" << text;
    }
    // A value that is no option is refused before anything is written.
    test::CliRun bad = test::runKiln(submitCommand(dir / "b", "--sbatch-arg=account"));
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--sbatch-arg takes one sbatch option"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "b"));
}

TEST(FarmQueue, AFailedSubmitLeavesNothingBehind) {
    auto dir = test::scratchDir();
    {
        test::ScopedEnv path("PATH", sbatchStandIn(dir, false) + ":" + std::getenv("PATH"));
        test::CliRun r = test::runKiln(submitCommand(dir, "--sbatch-arg=--account=nobody"));
        EXPECT_EQ(r.code, 1);
        EXPECT_NE(r.err.find("Invalid account"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "job")) << "a half-made job directory";
        EXPECT_FALSE(fs::exists(dir / "out")) << "the output folders submit made";
    }
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
