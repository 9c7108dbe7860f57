// kiln farm: shard plans, Slurm scripts and status parsing, then end to end against a real
// single-node Slurm cluster (tools/slurm_local.sh) started once for the suite.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "farm_test_support.h"
#include "renderer/farm/farm_status.h"
#include "renderer/farm/slurm.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using farm::ShardState;

const farm::RenderTask kTask{"/s/scene.obj", {"-r", "32", "24", "-s", "10"}, "/o/final"};

TEST(FarmPlan, SamplesSplitEveryRenderIntoRangesWithOneMergeEach) {
    farm::FarmJob job = farm::planFarmJob({kTask}, farm::ShardBy::Samples, 4, "/jobs/j");
    ASSERT_EQ(job.shards.size(), 4u);
    const std::vector<std::pair<std::string, std::string>> ranges{
        {"0", "2"}, {"2", "5"}, {"5", "7"}, {"7", "10"}};
    for (size_t i = 0; i < 4; ++i) {
        const auto& args = job.shards[i].tasks.at(0).args;
        ASSERT_GE(args.size(), 3u);
        EXPECT_EQ(args[args.size() - 3], "--sample-range");
        EXPECT_EQ(args[args.size() - 2], ranges[i].first);
        EXPECT_EQ(args.back(), ranges[i].second);
    }
    ASSERT_EQ(job.merges.size(), 1u);
    EXPECT_EQ(job.merges[0].output, "/o/final");
    EXPECT_EQ(job.merges[0].inputs[1], "/jobs/j/shards/r0000_p001");
    std::vector<std::string> merge = farm::mergeCommand(job.merges[0]);
    EXPECT_EQ(merge.front(), "merge");
    EXPECT_EQ(merge[1], "/jobs/j/shards/r0000_p000.ckpt");
    EXPECT_THROW(farm::planFarmJob({kTask}, farm::ShardBy::Samples, 11, "/j"),
                 farm::FarmInputError);
}

TEST(FarmPlan, RegionSplitsIntoStripesAndFramesIntoRuns) {
    farm::FarmJob region = farm::planFarmJob({kTask}, farm::ShardBy::Region, 4, "/j");
    const auto& args = region.shards[1].tasks[0].args;
    EXPECT_EQ(std::vector<std::string>(args.end() - 5, args.end()),
              (std::vector<std::string>{"--crop", "0", "1", "0.25", "0.5"}));
    std::vector<farm::RenderTask> frames(7, kTask);
    farm::FarmJob byFrames = farm::planFarmJob(frames, farm::ShardBy::Frames, 3, "/j");
    ASSERT_EQ(byFrames.shards.size(), 3u);
    EXPECT_EQ(byFrames.shards[0].tasks.size() + byFrames.shards[1].tasks.size() +
                  byFrames.shards[2].tasks.size(),
              7u);
    EXPECT_TRUE(byFrames.merges.empty());
    EXPECT_EQ(farm::planFarmJob(frames, farm::ShardBy::Frames, 50, "/j").shards.size(), 7u);
    // Chunks of a fixed size, the last one shorter (--frames-per-task).
    std::vector<farm::RenderTask> ten(10, kTask);
    for (size_t i = 0; i < ten.size(); ++i) ten[i].output += std::to_string(i);
    farm::FarmJob chunked = farm::planFarmJob(ten, farm::ShardBy::Frames, 1, "/j", 4);
    ASSERT_EQ(chunked.shards.size(), 3u);
    EXPECT_EQ(chunked.shards[0].tasks.size(), 4u);
    EXPECT_EQ(chunked.shards[1].tasks.size(), 4u);
    EXPECT_EQ(chunked.shards[1].tasks[0].output, "/o/final4");
    EXPECT_EQ(chunked.shards[2].tasks.size(), 2u);
    EXPECT_THROW(farm::parseShardBy("tiles"), farm::FarmInputError);
}

TEST(FarmPlan, ManifestRoundTrips) {
    fs::path dir = test::scratchDir();
    farm::FarmJob job = farm::planFarmJob({kTask}, farm::ShardBy::Samples, 2, dir.string());
    job.kiln = "/bin/kiln";
    job.sbatchOptions = {"--time=10"};
    job.submissions.push_back({12, 13, {0, 1}});
    farm::writeManifest(job);
    farm::FarmJob back = farm::readManifest(dir.string());
    EXPECT_EQ(back.dir, job.dir);
    EXPECT_EQ(back.shards[1].tasks[0].args, job.shards[1].tasks[0].args);
    EXPECT_EQ(back.merges[0].inputs, job.merges[0].inputs);
    EXPECT_EQ(back.submissions.at(0).mergeJob, 13);
    test::writeFile(dir / "manifest.json", "{\"dir\": 3}");
    EXPECT_THROW(farm::readManifest(dir.string()), farm::FarmInputError);
}

TEST(SlurmText, ScriptsRequeueCheckpointAndAppend) {
    farm::FarmJob job = farm::planFarmJob({kTask}, farm::ShardBy::Samples, 2, "/jobs/it's");
    job.kiln = "/opt/kiln";
    job.sbatchOptions = {"--partition=big"};
    std::string s = farm::shardScript(job);
    for (const char* line :
         {"#SBATCH --requeue\n", "#SBATCH --signal=B:TERM@60\n", "#SBATCH --open-mode=append\n",
          "#SBATCH --partition=big\n", "#SBATCH --output=/jobs/it's/logs/shard_%a.log\n",
          "exec '/opt/kiln' farm run-shard '/jobs/it'\\''s' "
          "\"$SLURM_ARRAY_TASK_ID\"\n"})
        EXPECT_NE(s.find(line), std::string::npos) << line << "\n" << s;
    EXPECT_NE(farm::mergeScript(job).find("farm merge"), std::string::npos);
}

TEST(SlurmText, ParsesArrayIdsAndScontrolRecords) {
    EXPECT_EQ(farm::parseArrayTaskIds("0-3"), (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(farm::parseArrayTaskIds("1,3,5-6%2"), (std::vector<int>{1, 3, 5, 6}));
    std::string text =
        "JobId=9 ArrayJobId=7 ArrayTaskId=2-3 JobName=kiln-shards JobState=PENDING "
        "Reason=Resources Dependency=(null) Restarts=0 ExitCode=0:0\n"
        "JobId=8 ArrayJobId=7 ArrayTaskId=1 JobName=kiln-shards JobState=FAILED "
        "Reason=NonZeroExitCode Restarts=0 ExitCode=2:0\n"
        "JobId=7 ArrayJobId=7 ArrayTaskId=0 JobName=kiln-shards JobState=RUNNING Reason=None "
        "Restarts=1 ExitCode=0:0\n";
    auto tasks = farm::parseScontrolArray(text);
    ASSERT_EQ(tasks.size(), 4u);
    EXPECT_EQ(tasks[0].state, "RUNNING");
    EXPECT_EQ(tasks[0].restarts, 1);
    EXPECT_EQ(tasks[1].exitCode, "2:0");
    EXPECT_EQ(tasks[3].state, "PENDING");
    EXPECT_EQ(farm::parseScontrolJob("JobId=10 JobState=CANCELLED Reason=Dependency").state,
              "CANCELLED");
    EXPECT_EQ(farm::stateFromSlurm("REQUEUED"), ShardState::Pending);
    EXPECT_EQ(farm::stateFromSlurm("COMPLETING"), ShardState::Running);
    EXPECT_EQ(farm::stateFromSlurm("TIMEOUT"), ShardState::Failed);
    EXPECT_EQ(farm::stateFromSlurm("UNKNOWN"), ShardState::Failed);
    EXPECT_EQ(farm::lastErrorLine("a\nkiln: error: x.obj: bad\nslurmstepd: done\n\n"),
              "kiln: error: x.obj: bad");
    EXPECT_EQ(farm::lastErrorLine("kiln render: unknown option '--x'\nkiln: [1/1] out: failed\n"),
              "kiln render: unknown option '--x'");
}

// Bad input is refused before anything is written or submitted: one line, exit 2.
TEST(FarmSubmit, RefusesBadInputBeforeSubmitting) {
    fs::path dir = test::scratchDir();
    std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    const std::vector<std::pair<std::vector<std::string>, std::string>> bad{
        {{scene, "-r", "16", "12", "--bogus", "--shards", "2"}, "--bogus"},
        {{scene, "--shards", "2", "--by", "tiles"}, "--by takes"},
        {{scene, "-s", "2", "--shards", "4", "--by", "samples"}, "cannot make 4 sample shards"},
        {{(dir / "missing.obj").string(), "--shards", "2"}, "does not exist"},
        {{scene, "--frames-per-task", "2", "--by", "samples"}, "--frames-per-task splits"},
        {{scene, "--frames-per-task", "0"}, "--frames-per-task"}};
    for (const auto& [args, message] : bad) {
        std::vector<std::string> all{"farm", "submit"};
        all.insert(all.end(), args.begin(), args.end());
        all.insert(all.end(), {"-d", (dir / "job").string()});
        farm::CommandResult r = test::kiln(all);
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "job")) << message;
    }
}

// A real slurmctld + slurmd + munged for the suite, in their own directory and on ports no other
// suite or a default cluster uses. Tests fail with the reason when it cannot start.
class FarmCluster : public ::testing::Test {
  protected:
    // Ports below Linux's ephemeral range (32768 up), where the local end of any client's
    // connection (another suite's sbatch and squeue) may already hold the port slurmctld binds.
    // A start that fails tries two more port pairs; the error keeps every attempt's output.
    static void SetUpTestSuite() {
        for (int attempt = 0; attempt < 3; ++attempt) {
            const int base = 20000 + int((::getpid() + attempt * 2003) % 6000) * 2;
            slurmDir() = (fs::temp_directory_path() / "kiln-tests" /
                          fmt::format("slurm-{}-{}", ::getpid(), attempt))
                             .string();
            ::setenv("KILN_SLURM_DIR", slurmDir().c_str(), 1);
            ::setenv("KILN_SLURM_CTLD_PORT", std::to_string(base).c_str(), 1);
            ::setenv("KILN_SLURM_SLURMD_PORT", std::to_string(base + 1).c_str(), 1);
            farm::CommandResult r =
                farm::runCapturing(test::repo("tools/slurm_local.sh"), {"start"});
            size_t at = r.output.find("export SLURM_CONF=");
            if (r.exitCode == 0 && at != std::string::npos) {
                std::string conf = r.output.substr(at + 18);
                ::setenv("SLURM_CONF", conf.substr(0, conf.find('\n')).c_str(), 1);
                startError().clear();
                return;
            }
            startError() += fmt::format(
                "tools/slurm_local.sh start on ports {}, {} failed (exit "
                "{}):\n{}\n",
                base, base + 1, r.exitCode, r.output);
        }
    }
    static void TearDownTestSuite() {
        farm::runCapturing(test::repo("tools/slurm_local.sh"), {"stop"});
    }
    void SetUp() override { ASSERT_EQ(startError(), "") << "no Slurm cluster"; }

    static std::string& slurmDir() {
        static std::string dir;
        return dir;
    }
    static std::string& startError() {
        static std::string error;
        return error;
    }

    // Polls the job's status until `done` holds; fails after `seconds`.
    static farm::FarmStatus waitFor(const std::string& dir,
                                    const std::function<bool(const farm::FarmStatus&)>& done,
                                    double seconds = 60) {
        auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        farm::FarmStatus status;
        while (std::chrono::steady_clock::now() < until) {
            farm::FarmJob job = farm::readManifest(dir);
            status = farm::farmStatus(job);
            if (done(status)) return status;
            std::this_thread::sleep_for(std::chrono::milliseconds(250));
        }
        farm::FarmJob job = farm::readManifest(dir);
        ADD_FAILURE() << "timed out after " << seconds << " s:\n"
                      << farm::statusText(job, status)
                      << test::kiln({"farm", "status", dir}).output;
        return status;
    }
    static bool finished(const farm::FarmStatus& s) {
        return s.count(ShardState::Failed) > 0 ||
               (s.count(ShardState::Done) == s.shards.size() && s.merged);
    }
    static bool settled(const farm::FarmStatus& s) {
        return s.count(ShardState::Running) == 0 && s.count(ShardState::Pending) == 0;
    }
};

std::string scene() { return test::cs184("sky/CBspheres_lambertian.dae"); }

farm::CommandResult submit(const std::vector<std::string>& args) {
    std::vector<std::string> all{"farm", "submit"};
    all.insert(all.end(), args.begin(), args.end());
    return test::kiln(all);
}

// The same render in one process, the reference for the shards.
std::string referenceRender(const fs::path& dir, const std::vector<std::string>& options) {
    std::vector<std::string> args{"render", scene(), "-q", "-o", (dir / "one").string()};
    args.insert(args.end(), options.begin(), options.end());
    farm::CommandResult r = test::kiln(args);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return (dir / "one.exr").string();
}

// Waits on the checkpoint/resume/merge branch (#16): --sample-range, --resume, kiln merge.
TEST_F(FarmCluster, FourShardsBySamplesAndByRegionEqualTheOneProcessRender) {
    fs::path dir = test::scratchDir();
    const std::vector<std::string> options{"-r", "32", "24", "-s", "8"};
    for (const char* by : {"samples", "region"}) {
        std::vector<std::string> args{scene()};
        args.insert(args.end(), options.begin(), options.end());
        args.insert(args.end(), {"--shards", "4", "--by", by, "-d", (dir / by).string(), "-o",
                                 (dir / by / "image").string(), "--checkpoint-every", "1"});
        farm::CommandResult r = submit(args);
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }
    std::string reference = referenceRender(dir, options);
    for (const char* by : {"samples", "region"}) {
        farm::FarmStatus s = waitFor((dir / by).string(), finished);
        ASSERT_TRUE(s.merged) << by << "\n"
                              << test::kiln({"farm", "status", (dir / by).string()}).output;
        EXPECT_EQ(test::exrDifference((dir / by / "image.exr").string(), reference), "") << by;
    }
}

// --sbatch-arg reaches Slurm itself (the job's comment as slurmctld holds it), and a submit that
// Slurm refuses (no such partition) exits 1 and leaves neither the job folder nor the output
// folders behind.
TEST_F(FarmCluster, SbatchArgsReachSlurmAndARefusedSubmitLeavesNothing) {
    fs::path dir = test::scratchDir();
    const std::vector<std::string> render{scene(), "-r",       "16", "12",   "-s",
                                          "4",     "--shards", "2",  "--by", "samples"};
    std::vector<std::string> args = render;
    args.insert(args.end(), {"-d", (dir / "ok").string(), "-o", (dir / "ok/image").string(),
                             "--sbatch-arg=--comment=kiln-wrangler-test"});
    farm::CommandResult r = submit(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    farm::FarmStatus s = waitFor((dir / "ok").string(), finished);
    EXPECT_TRUE(s.merged);
    farm::CommandResult shown = farm::runCapturing("scontrol", {"show", "job"});
    EXPECT_NE(shown.output.find("Comment=kiln-wrangler-test"), std::string::npos) << shown.output;

    args = render;
    args.insert(args.end(),
                {"-d", (dir / "no/job").string(), "-o", (dir / "no/out/deep/image").string(),
                 "--sbatch-arg=--partition=no-such-partition"});
    r = submit(args);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("artition"), std::string::npos) << r.output;  // Slurm's reason
    EXPECT_FALSE(fs::exists(dir / "no/job")) << "a half-made job directory";
    EXPECT_FALSE(fs::exists(dir / "no/out")) << "the output folders submit made";
}

// Waits on #16. A shard killed and requeued by Slurm while it renders comes back, resumes from
// its checkpoint, and the merged image is still the one-process render bit for bit.
TEST_F(FarmCluster, RequeuedShardResumesFromItsCheckpoint) {
    fs::path dir = test::scratchDir();
    // About 5 s per one-thread shard here: long enough to be caught mid-render. The thread count
    // does not change the image, so the reference renders with all cores.
    const std::vector<std::string> options{"-r", "32", "24", "-s", "12000"};
    std::vector<std::string> args{scene()};
    args.insert(args.end(), options.begin(), options.end());
    args.insert(args.end(), {"-t", "1", "--shards", "2", "--by", "samples", "-d", dir.string(),
                             "--checkpoint-every", "1"});
    farm::CommandResult r = submit(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    farm::FarmJob job = farm::readManifest(dir.string());
    long array = job.submissions.at(0).arrayJob;
    std::string shard0 = job.shards[0].tasks[0].output;
    auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!fs::exists(shard0 + ".ckpt") && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_TRUE(fs::exists(shard0 + ".ckpt")) << "shard 0 wrote no checkpoint while rendering";
    ASSERT_FALSE(farm::shardComplete(job, 0)) << "shard 0 finished before it could be killed";
    farm::CommandResult requeue =
        farm::runCapturing("scontrol", {"requeue", std::to_string(array) + "_0"});
    ASSERT_EQ(requeue.exitCode, 0) << requeue.output;
    std::string reference = referenceRender(dir, options);
    farm::FarmStatus s = waitFor(dir.string(), finished, 90);
    ASSERT_TRUE(s.merged) << farm::statusText(job, s);
    EXPECT_GE(s.shards[0].slurm.restarts, 1);
    std::string log = farm::readFileText(farm::shardLogPath(job, 0));
    EXPECT_NE(log.find("resuming from its checkpoint"), std::string::npos) << log;
    EXPECT_EQ(test::exrDifference((dir / "one.exr").string(), job.merges[0].output + ".exr"), "");
}

// A job file of 8 turntable frames becomes an 8-task array that writes the 8 frames; submitting
// the same file again submits nothing.
TEST_F(FarmCluster, TurntableOfEightFramesRunsAsAnArrayOnce) {
    fs::path dir = test::scratchDir();
    std::string file = test::writeTurntableJob(dir / "turntable.json", "frames/{scene}_{frame:02}",
                                               scene(), {"-r", 16, 12, "-s", 1, "-t", 1}, 8);
    std::vector<std::string> args{
        file, "--shards", "8", "--by", "frames", "-d", (dir / "job").string()};
    farm::CommandResult r = submit(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    farm::FarmStatus s = waitFor((dir / "job").string(), finished);
    ASSERT_EQ(s.count(ShardState::Done), 8u);
    for (int k = 0; k < 8; ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "frames/CBspheres_lambertian_%02d.exr", k);
        EXPECT_TRUE(fs::exists(dir / name)) << name;
    }
    farm::CommandResult again = submit(args);
    EXPECT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("nothing submitted"), std::string::npos) << again.output;
    EXPECT_EQ(farm::readManifest((dir / "job").string()).submissions.size(), 1u);
}

// Issue #28: --frames-per-task 4 makes an 8-frame turntable two array tasks, each of which loads
// the scene once for its four frames (the shard log says so); the frames equal one-frame renders.
TEST_F(FarmCluster, FramesPerTaskLoadsTheSceneOncePerTask) {
    fs::path dir = test::scratchDir();
    std::string file = test::writeTurntableJob(dir / "turntable.json", "frames/{frame}", scene(),
                                               {"-r", 16, 12, "-s", 1, "-t", 1}, 8);
    std::string jobDir = (dir / "job").string();
    farm::CommandResult r = submit({file, "--frames-per-task", "4", "-d", jobDir});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    farm::FarmJob job = farm::readManifest(jobDir);
    ASSERT_EQ(job.shards.size(), 2u);
    farm::FarmStatus s = waitFor(jobDir, finished);
    ASSERT_EQ(s.count(ShardState::Done), 2u);
    for (int shard = 0; shard < 2; ++shard) {
        std::string log = farm::readFileText(farm::shardLogPath(job, shard));
        EXPECT_NE(log.find("this process: 4 renders, 1 scene loads, 1 accelerator builds"),
                  std::string::npos)
            << log;
    }
    std::string reference =
        referenceRender(dir, {"-r", "16", "12", "-s", "1", "--turntable", "8", "--frame", "5"});
    EXPECT_EQ(test::exrDifference((dir / "frames/5.exr").string(), reference), "");
}

// A shard whose scene cannot be read fails; farm status shows it failed with its log line, and
// resubmit runs that shard alone once the scene is mended.
TEST_F(FarmCluster, FailedShardShowsInStatusAndResubmitRunsOnlyIt) {
    fs::path dir = test::scratchDir();
    std::string bad = test::writeFile(dir / "broken.obj", "v 0 0 0\nf 1 2 3\n");
    std::string file = test::writeFile(dir / "job.json", R"({
      "output": "out/{scene}",
      "scenes": [")" + scene() + R"(", "broken.obj"],
      "args": ["-r", 16, 12, "-s", 1, "-t", 1]
    })");
    std::string jobDir = (dir / "job").string();
    farm::CommandResult r = submit({file, "--shards", "2", "-d", jobDir});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    farm::FarmStatus s = waitFor(jobDir, settled);
    EXPECT_EQ(s.shards[0].state, ShardState::Done);
    EXPECT_EQ(s.shards[1].state, ShardState::Failed);
    EXPECT_NE(s.shards[1].logLine.find("broken.obj"), std::string::npos) << s.shards[1].logLine;
    farm::CommandResult status = test::kiln({"farm", "status", jobDir});
    EXPECT_EQ(status.exitCode, 1);
    EXPECT_NE(status.output.find("shard 1: failed"), std::string::npos) << status.output;
    EXPECT_NE(status.output.find("broken.obj"), std::string::npos) << status.output;

    auto firstWrite = fs::last_write_time(dir / "out/CBspheres_lambertian.exr");
    test::writeFile(bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    farm::CommandResult again = test::kiln({"farm", "resubmit", jobDir});
    ASSERT_EQ(again.exitCode, 0) << again.output;
    s = waitFor(jobDir, finished);
    EXPECT_EQ(s.count(ShardState::Done), 2u);
    EXPECT_EQ(fs::last_write_time(dir / "out/CBspheres_lambertian.exr"), firstWrite);
    farm::FarmJob job = farm::readManifest(jobDir);
    ASSERT_EQ(job.submissions.size(), 2u);
    EXPECT_EQ(job.submissions[1].shards, std::vector<int>{1});
}

}  // namespace
}  // namespace kiln
