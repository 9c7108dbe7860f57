// Batch job files, the turntable and camera override, and `kiln batch` end to end.
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <nlohmann/json.hpp>
#include <thread>

#include "farm_test_support.h"
#include "renderer/farm/job_file.h"
#include "renderer/farm/render_task.h"
#include "renderer/geometry/turntable.h"

extern char** environ;

namespace kiln {
namespace {

namespace fs = std::filesystem;

bool contains(const std::vector<std::string>& args, const std::vector<std::string>& run) {
    return std::search(args.begin(), args.end(), run.begin(), run.end()) != args.end();
}

TEST(JobFile, ExpandsScenesCamerasFramesAndSettings) {
    fs::path dir = test::scratchDir();
    test::writeFile(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    test::writeFile(dir / "b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string file = test::writeFile(dir / "job.json", R"({
      "output": "out/{scene}_{camera}_{frame:03}_{settings}",
      "scenes": ["a.obj", "b.obj"],
      "args": ["-r", 32, 24],
      "cameras": [
        {"name": "orbit", "turntable": 8, "frames": [2, 5], "axis": [0, 0, 1]},
        {"name": "front", "position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30},
        {"name": "fly", "path": [{"position": [1, 0, 5]}, {"position": [2, 0, 5]}]}
      ],
      "settings": [{"name": "lo", "args": ["-s", 2]}, {"name": "hi", "args": ["-s", 16]}]
    })");
    std::vector<farm::RenderTask> tasks = farm::readJobFile(file);
    ASSERT_EQ(tasks.size(), 2u * (3 + 1 + 2) * 2);
    const farm::RenderTask& first = tasks[0];
    EXPECT_EQ(first.scene, fs::absolute(dir / "a.obj").lexically_normal().string());
    EXPECT_EQ(first.output, (dir / "out/a_orbit_002_lo").string());
    EXPECT_TRUE(contains(first.args, {"-r", "32", "24"}));
    EXPECT_TRUE(contains(first.args, {"--orbit-axis", "0", "0", "1"}));
    EXPECT_TRUE(contains(first.args, {"--turntable", "8", "--frame", "2"}));
    EXPECT_TRUE(contains(first.args, {"-s", "2"}));
    EXPECT_EQ(tasks[5].output, (dir / "out/a_orbit_004_hi").string());
    EXPECT_TRUE(contains(tasks[6].args,
                         {"--position", "0", "0", "5", "--look-at", "0", "0", "0", "--fov", "30"}));
    EXPECT_EQ(tasks[10].output, (dir / "out/a_fly_001_lo").string());
    EXPECT_TRUE(contains(tasks[10].args, {"--position", "2", "0", "5"}));
    EXPECT_EQ(tasks.back().output, (dir / "out/b_fly_001_hi").string());
}

TEST(JobFile, OutputVariables) {
    farm::OutputVariables v{"bunny", "orbit", "final", 7, 12};
    EXPECT_EQ(farm::expandOutputName("{scene}/{camera}.{frame:04}.{settings}.{index}", v),
              "bunny/orbit.0007.final.12");
    EXPECT_THROW(farm::expandOutputName("{scene}_{shot}", v), farm::FarmInputError);
    EXPECT_THROW(farm::expandOutputName("{scene", v), farm::FarmInputError);
}

// Each malformed job file is refused with a message naming the file, before anything renders.
TEST(JobFile, RefusesMalformedFiles) {
    fs::path dir = test::scratchDir();
    test::writeFile(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::vector<std::pair<std::string, std::string>> bad{
        {"{\"output\": \"x\", \"scenes\": [\"a.obj\"]", "not valid JSON"},
        {R"({"output": "x", "scenes": ["a.obj"], "camras": []})", "unknown key 'camras'"},
        {R"({"output": "x", "scenes": ["missing.obj"]})", "does not exist"},
        {R"({"scenes": ["a.obj"]})", "needs 'output'"},
        {R"({"output": "x", "scenes": []})", "non-empty array"},
        {R"({"output": "x", "scenes": ["a.obj"], "cameras": [{"turntable": 4}]})",
         "two renders write"},
        {R"({"output": "x{frame}", "scenes": ["a.obj"], "cameras": [{"turntable": 0}]})",
         "integer in 1.."},
        {R"({"output": "x{frame}", "scenes": ["a.obj"], "cameras": [{"position": [1, 2]}]})",
         "three numbers"},
        {R"({"output": "x{take}", "scenes": ["a.obj"]})", "unknown variable"}};
    for (const auto& [text, message] : bad) {
        std::string file = test::writeFile(dir / "bad.json", text);
        try {
            farm::readJobFile(file);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const farm::FarmInputError& e) {
            EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    }
    // Through the command: exit 2 and one line (one case is enough, the message is the same).
    farm::CommandResult r = test::kiln({"batch", (dir / "bad.json").string()});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

// Issue #33 item 6: every render of a job file goes through kiln render's own checks before the
// first one starts; the error names the job file, the entry and the field (or the render, when
// only the combination fails), exit 2, one line, nothing rendered.
TEST(JobFile, BadRenderValuesAreRefusedUpFrontNamingTheEntryAndField) {
    fs::path dir = test::scratchDir();
    test::writeFile(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string head =
        R"("output": "out/{camera}_{frame}_{settings}", "scenes": ["a.obj"], )";
    const std::vector<std::pair<std::string, std::string>> bad{
        {R"("settings": [{"args": ["-s", 4]}, {"args": ["-s", 0]}])", "settings[1]: 'args': "},
        {R"("args": ["-r", 16, 12, 7])", "job.json: 'args': needs exactly one scene file; '7'"},
        {R"("cameras": [{"position": [0, 0, 5], "up": [0, 1e39, 0]}])",
         "job.json: cameras[0]: 'up': --up takes finite coordinates"},
        {R"("cameras": [{"turntable": 4, "centre": [1e39, 0, 0]}])",
         "job.json: cameras[0]: 'centre': --orbit-centre takes finite coordinates"},
        {R"("cameras": [{"name": "fly", "path": [{"position": [0, 0, 5]}, {"position": [1, 1, 1], "look_at": [1, 1, 1]}]}])",
         "job.json: the render of scene 'a.obj', camera 'fly', frame 1: --position and --look-at "
         "are the same point"},
        {R"("args": ["--display", "no such display"])", "job.json: 'args': "}};
    for (const auto& [body, message] : bad) {
        std::string file = test::writeFile(dir / "job.json", "{" + head + body + "}");
        farm::CommandResult r = test::kiln({"batch", file, "-q"});
        EXPECT_EQ(r.exitCode, 2) << body << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "out")) << body;
    }
    // The same job with good values runs.
    std::string good = test::writeFile(
        dir / "job.json",
        "{" + head +
            R"("args": ["-r", 8, 6, "-s", 1], "cameras": [{"position": [0.3, 0.3, 4], "up": [0, 1, 0]}]})");
    farm::CommandResult r = test::kiln({"batch", good, "-q"});
    EXPECT_EQ(r.exitCode, 0) << r.output;
}

TEST(Turntable, OrbitKeepsDistanceAndAim) {
    Camera cam;
    cam.position = Vec3(1, 2, 7);
    Vec3 centre(1, 2, 2);
    pointCamera(cam, cam.position, centre, Vec3(0, 1, 0));
    Camera same = orbitCamera(cam, centre, Vec3(0, 1, 0), 8, 0);
    EXPECT_EQ(same.position, cam.position);
    EXPECT_EQ(same.forward, cam.forward);
    // A quarter turn about +y (right-handed) takes +z to +x.
    Camera quarter = orbitCamera(cam, centre, Vec3(0, 2, 0), 8, 2);
    EXPECT_NEAR(quarter.position.x, 6.0f, 1e-5f);
    EXPECT_NEAR(quarter.position.y, 2.0f, 1e-5f);
    EXPECT_NEAR(quarter.position.z, 2.0f, 1e-5f);
    for (int k = 0; k < 8; ++k) {
        Camera c = orbitCamera(cam, centre, Vec3(0, 1, 0), 8, k);
        EXPECT_NEAR(length(c.position - centre), 5.0f, 1e-5f);
        Vec3 aim = normalize(centre - c.position);
        EXPECT_NEAR(dot(aim, c.forward), 1.0f, 1e-6f) << k;
        EXPECT_NEAR(dot(c.up, c.forward), 0.0f, 1e-6f) << k;
    }
    EXPECT_THROW(orbitCamera(cam, centre, Vec3(0, 1, 0), 8, 8), std::invalid_argument);
    EXPECT_THROW(orbitCamera(cam, centre, Vec3(0, 0, 0), 8, 1), std::invalid_argument);
    EXPECT_THROW(pointCamera(cam, centre, centre, Vec3(0, 1, 0)), std::invalid_argument);
}

// kiln render's camera options: frame 0 of a turntable is the framed camera bit for bit, other
// frames and an override change the image, impossible cameras are refused with exit 2.
TEST(CameraOptions, TurntableAndOverrideThroughKilnRender) {
    fs::path dir = test::scratchDir();
    std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    auto render = [&](const std::string& name, std::vector<std::string> extra) {
        std::vector<std::string> args{"render", scene, "-r", "16", "12",
                                      "-s",     "2",   "-q", "-o", (dir / name).string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return test::kiln(args);
    };
    ASSERT_EQ(render("plain", {}).exitCode, 0);
    ASSERT_EQ(render("frame0", {"--turntable", "4", "--frame", "0"}).exitCode, 0);
    ASSERT_EQ(render("frame1", {"--turntable", "4", "--frame", "1"}).exitCode, 0);
    ASSERT_EQ(render("moved", {"--position", "0", "1", "4", "--fov", "60"}).exitCode, 0);
    auto exr = [&](const std::string& name) { return (dir / (name + ".exr")).string(); };
    EXPECT_EQ(test::exrDifference(exr("plain"), exr("frame0")), "");
    EXPECT_NE(test::exrDifference(exr("plain"), exr("frame1")), "");
    EXPECT_NE(test::exrDifference(exr("plain"), exr("moved")), "");
    for (const auto& bad : std::vector<std::vector<std::string>>{
             {"--frame", "1"},
             {"--fov", "180"},
             {"--orbit-axis", "0", "0", "0", "--turntable", "2", "--frame", "1"}}) {
        farm::CommandResult r = render("bad", bad);
        EXPECT_EQ(r.exitCode, 2) << bad[0] << ": " << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }
}

// Waits on the checkpoint/resume branch (#16): renders pass --resume --checkpoint-every.
// Two frames render; a second run skips both.
TEST(Batch, SkipsCompleteOutputsAndReportsJson) {
    fs::path dir = test::scratchDir();
    std::string job = test::writeTurntableJob(dir / "job.json", "out/{camera}_{frame}",
                                              test::cs184("sky/CBspheres_lambertian.dae"),
                                              {"-r", 16, 12, "-s", 2}, 2);
    farm::CommandResult first = test::kiln({"batch", job, "--json", "-q"});
    ASSERT_EQ(first.exitCode, 0) << first.output;
    EXPECT_TRUE(fs::exists(dir / "out/orbit_0.exr"));
    EXPECT_TRUE(fs::exists(dir / "out/orbit_1.png"));
    farm::CommandResult second = test::kiln({"batch", job, "--json", "-q"});
    ASSERT_EQ(second.exitCode, 0) << second.output;
    // stdout's document (stderr's lines are JSON lines too with --json).
    auto json = nlohmann::json::parse(second.output.substr(second.output.find("{\n")));
    EXPECT_EQ(json["counts"]["skipped"], 2);
    EXPECT_EQ(json["counts"]["rendered"], 0);
    // -q changes what the renders print, not what they write: still complete without it.
    farm::CommandResult loud = test::kiln({"batch", job, "--json"});
    ASSERT_EQ(loud.exitCode, 0) << loud.output;
    json = nlohmann::json::parse(loud.output.substr(loud.output.find("{\n")));
    EXPECT_EQ(json["counts"]["skipped"], 2) << loud.output;
}

// Waits on #16. Ctrl-C reaches the running render through kiln batch, which exits 130 with the
// render's checkpoint on disk; the next kiln batch resumes it, and the image is the uninterrupted
// render's bit for bit.
TEST(Batch, InterruptedRenderResumesBitForBit) {
    fs::path dir = test::scratchDir();
    // Several seconds on one thread, so the interrupt lands mid-render, well after the first
    // checkpoint; the thread count does not change the image, so the reference uses every core.
    const std::vector<std::string> options{"-r", "32", "24", "-s", "6000"};
    nlohmann::json args = options;
    args.push_back("-t");
    args.push_back("1");
    std::string job = test::writeFile(
        dir / "job.json", nlohmann::json{{"output", "resumed"},
                                         {"scenes", {test::cs184("sky/CBspheres_lambertian.dae")}},
                                         {"args", args}}
                              .dump());
    std::string program = KILN_BINARY;
    std::vector<char*> argv{program.data(),
                            const_cast<char*>("batch"),
                            job.data(),
                            const_cast<char*>("-q"),
                            const_cast<char*>("--checkpoint-every"),
                            const_cast<char*>("1"),
                            nullptr};
    pid_t pid = 0;
    ASSERT_EQ(::posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ), 0);
    int status = 0;
    bool exited = false;
    auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!fs::exists(dir / "resumed.ckpt") && std::chrono::steady_clock::now() < until &&
           !(exited = ::waitpid(pid, &status, WNOHANG) == pid))
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!exited) {
        ::kill(pid, SIGINT);
        ::waitpid(pid, &status, 0);
    }
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), 130) << "the render finished before it could be interrupted";
    farm::CommandResult again = test::kiln({"batch", job, "-q", "--json"});
    ASSERT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("\"resumed\": 1"), std::string::npos) << again.output;
    std::vector<std::string> one{"render", test::cs184("sky/CBspheres_lambertian.dae"), "-q", "-o",
                                 (dir / "one").string()};
    one.insert(one.end(), options.begin(), options.end());
    ASSERT_EQ(test::kiln(one).exitCode, 0);
    EXPECT_EQ(test::exrDifference((dir / "one.exr").string(), (dir / "resumed.exr").string()), "");
}

// Issue #28: the frames of one scene that differ only in camera (a turntable and a camera path)
// render in one child from one scene load and one accelerator build, which the child's own
// counters say; every frame is the one-frame render bit for bit; a second batch skips them all.
TEST(Batch, FramesOfOneSceneLoadItOnceAndEqualSingleRenders) {
    fs::path dir = test::scratchDir();
    const std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    std::string job = test::writeFile(dir / "job.json", R"({
      "output": "out/{camera}_{frame}",
      "scenes": [")" + scene + R"("],
      "args": ["-r", 16, 12, "-s", 2],
      "cameras": [{"name": "orbit", "turntable": 4},
                  {"name": "fly", "path": [{"position": [0, 1, 4]}, {"position": [1, 1, 4], "fov": 50}]}]
    })");
    // At debug the batch lets its renders' info lines through: their load counters.
    farm::CommandResult r = test::kiln({"batch", job, "-q", "--log-level", "debug"});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("6 renders from one scene load"), std::string::npos) << r.output;
    // The batch's child writes checkpoints: their fingerprint reads the scene file once per load
    // too, not once per frame (a 100M-triangle scene's file is gigabytes).
    EXPECT_NE(r.output.find("this process: 6 renders, 1 scene loads, 1 accelerator builds, 1 scene "
                            "checksums"),
              std::string::npos)
        << r.output;
    std::vector<farm::RenderTask> tasks = farm::readJobFile(job);
    ASSERT_EQ(tasks.size(), 6u);
    for (size_t k = 0; k < tasks.size(); ++k) {
        std::vector<std::string> alone{"render", scene, "-q", "-o", (dir / "alone").string()};
        alone.insert(alone.end(), tasks[k].args.begin(), tasks[k].args.end());
        ASSERT_EQ(test::kiln(alone).exitCode, 0);
        EXPECT_EQ(test::exrDifference((dir / "alone.exr").string(), tasks[k].output + ".exr"), "")
            << tasks[k].output;
    }
    farm::CommandResult again = test::kiln({"batch", job, "-q", "--json"});
    ASSERT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("\"skipped\": 6"), std::string::npos) << again.output;
}

// A finished frame's checkpoint is removed by the batch (unless --keep-checkpoints): its render
// does not write one at its end only for that (0.7 GB at 1080p), and frames stay complete
// whichever way the batch ran.
TEST(Batch, FinishedFramesWriteNoCheckpointUnlessKept) {
    fs::path dir = test::scratchDir();
    std::string job = test::writeTurntableJob(dir / "job.json", "out/{camera}_{frame}",
                                              test::cs184("sky/CBspheres_lambertian.dae"),
                                              {"-r", 16, 12, "-s", 2}, 2);
    farm::CommandResult dropped = test::kiln({"batch", job, "-q", "--log-level", "debug"});
    ASSERT_EQ(dropped.exitCode, 0) << dropped.output;
    EXPECT_EQ(dropped.output.find("MiB written in"), std::string::npos) << dropped.output;
    EXPECT_FALSE(fs::exists(dir / "out/orbit_0.ckpt"));
    fs::remove_all(dir / "out");
    farm::CommandResult kept =
        test::kiln({"batch", job, "-q", "--keep-checkpoints", "--log-level", "debug"});
    ASSERT_EQ(kept.exitCode, 0) << kept.output;
    EXPECT_NE(kept.output.find("MiB written in"), std::string::npos) << kept.output;
    EXPECT_TRUE(fs::exists(dir / "out/orbit_1.ckpt"));
    farm::CommandResult again = test::kiln({"batch", job, "-q", "--json"});
    ASSERT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("\"skipped\": 2"), std::string::npos) << again.output;
}

// A child's done marker records the command as it ran, --no-final-checkpoint included: the frame
// stays complete for a batch or farm task that checks the command without it (a child killed
// before its batch rewrote the marker must not render its finished frames again).
TEST(Batch, ADoneMarkerIgnoresWhatOnlyChangesWhatARenderKeeps) {
    fs::path dir = test::scratchDir();
    const std::string out = (dir / "f").string();
    test::writeFile(out + ".exr", "an image");
    const std::vector<std::string> command{"render", "scene.obj", "-s", "4", "-o", out};
    std::vector<std::string> asRun = command;
    asRun.insert(asRun.end(), {"--no-final-checkpoint", "-q"});
    farm::markComplete(out, asRun);
    EXPECT_TRUE(farm::isComplete(out, command));
    std::vector<std::string> other = command;
    other[3] = "8";
    EXPECT_FALSE(farm::isComplete(out, other));
}

// A frame that fails in the middle of a run (its EXR path is a directory) fails alone: the frames
// before it are done, the ones after it render in the next child, the batch exits 1.
TEST(Batch, AFailedFrameDoesNotStopTheFramesAfterIt) {
    fs::path dir = test::scratchDir();
    std::string job = test::writeTurntableJob(dir / "job.json", "out/{frame}",
                                              test::cs184("sky/CBspheres_lambertian.dae"),
                                              {"-r", 8, 6, "-s", 1}, 4);
    fs::create_directories(dir / "out/1.exr");
    farm::CommandResult r = test::kiln({"batch", job, "-q", "--json"});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    auto json = nlohmann::json::parse(r.output.substr(r.output.find("{\n")));
    EXPECT_EQ(json["counts"]["rendered"], 3);
    EXPECT_EQ(json["counts"]["failed"], 1);
    EXPECT_EQ(json["renders"][1]["outcome"], "failed");
    for (const char* done : {"out/0.done", "out/2.done", "out/3.done"})
        EXPECT_TRUE(fs::exists(dir / done)) << done;
    EXPECT_FALSE(fs::exists(dir / "out/1.done"));
}

// The checkpoint fingerprint's checksum of the scene file is read once per load: a reload (other
// load options) reads it again, and a frame resumes a checkpoint a lone kiln render wrote (the
// fingerprint is the same either way).
TEST(RenderFrames, ChecksumsTheSceneOncePerLoadAndResumesALoneRendersCheckpoint) {
    fs::path dir = test::scratchDir();
    const std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    auto frame = [&](const std::string& name, const std::string& spp,
                     std::vector<std::string> extra) {
        std::vector<std::string> args{scene,      "-r",
                                      "8",        "6",
                                      "-s",       spp,
                                      "-o",       (dir / name).string(),
                                      "--resume", "--checkpoint-every",
                                      "60"};
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    };
    std::vector<std::string> alone{"render"};
    for (const std::string& a : frame("a", "1", {"-q"})) alone.push_back(a);
    ASSERT_EQ(test::kiln(alone).exitCode, 0);
    std::vector<std::string> args{"render-frames"};
    for (const auto& f : {frame("a", "2", {}), frame("b", "1", {"--fov", "40"}),
                          frame("c", "1", {"--emitters", "camera"}),
                          frame("d", "1", {"--emitters", "camera", "--fov", "40"})}) {
        if (args.size() > 1) args.push_back("--then");
        args.insert(args.end(), f.begin(), f.end());
    }
    farm::CommandResult r = test::kiln(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("resuming " + (dir / "a.ckpt").string()), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("this process: 4 renders, 2 scene loads, 2 accelerator builds, 2 scene "
                            "checksums (this render reuses the scene and accelerator"),
              std::string::npos)
        << r.output;
}

// kiln render-frames reloads when the load options change (--emitters here), rebuilds only the
// accelerator when -t does (Embree's build keeps to the threads of the render that made it), and
// reuses both when only the camera or the other render options do.
TEST(RenderFrames, ReloadsOnlyForOtherLoadOptions) {
    fs::path dir = test::scratchDir();
    const std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    auto frame = [&](const std::string& name, std::vector<std::string> extra) {
        std::vector<std::string> args{
            scene, "-r", "8", "6", "-s", "1", "-q", "-o", (dir / name).string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    };
    std::vector<std::string> args{"render-frames"};
    for (const auto& f :
         {frame("a", {}), frame("b", {"--fov", "40", "-s", "2"}),
          frame("c", {"--emitters", "camera"}), frame("d", {"--emitters", "camera"}),
          frame("e", {"--emitters", "camera", "-t", "1"})}) {
        if (args.size() > 1) args.push_back("--then");
        args.insert(args.end(), f.begin(), f.end());
    }
    farm::CommandResult r = test::kiln(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("this process: 5 renders, 2 scene loads, 3 accelerator builds, 0 scene "
                            "checksums (this render reuses the scene of the one before)"),
              std::string::npos)
        << r.output;
    for (const char* name : {"a.done", "b.done", "c.done", "d.done", "e.done"})
        EXPECT_TRUE(fs::exists(dir / name)) << name;
    // Without -o there is no marker to write: refused before anything renders.
    farm::CommandResult bad = test::kiln({"render-frames", scene, "-r", "8", "6", "-q"});
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_NE(bad.output.find("needs -o"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace kiln
