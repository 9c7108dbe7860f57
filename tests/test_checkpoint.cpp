// Checkpoints and resume: the film saved exactly, a render killed at any moment and resumed equals
// the uninterrupted one bit for bit, refinement, refusals, and a full disk during a checkpoint.
#include <fmt/format.h>
#include <sys/mount.h>

#include <nlohmann/json.hpp>
#include <random>

#include "color/atomic_file.h"
#include "kiln_run.h"
#include "long_render_support.h"
#include "renderer/long_render.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// An in-process render of CBspheres through runLongRender, checkpointing to ckpt.
struct SmallRender : test::LoadedSpheres {
    RenderJobOptions options(int spp, int adaptiveBatch = 0) const {
        RenderJobOptions o = test::jobOptions(24, 18, spp, {}, AovRequest::defaults());
        o.settings.adaptiveBatch = adaptiveBatch;
        o.settings.adaptiveTolerance = 0.2f;
        return o;
    }
    LongRenderResult run(const RenderJobOptions& o, const std::string& ckpt, bool resume) const {
        RenderJob job(scene, *accel, o);
        LongRenderOptions lo;
        lo.checkpointPath = ckpt;
        lo.resume = resume;
        lo.fingerprint = checkpointFingerprint(job, test::spheres(), {});
        return runLongRender(job, lo);
    }
};

TEST(Checkpoint, RoundTripHoldsEveryBufferOfTheFilmExactly) {
    SmallRender r;
    std::string ckpt = (test::scratchDir() / "a.ckpt").string();
    LongRenderResult done = r.run(r.options(8, 4), ckpt, false);
    CheckpointInfo info;
    Film back = readCheckpoint(ckpt, info);
    EXPECT_EQ(test::filmState(back), test::filmState(done.film));
    EXPECT_TRUE(info.complete);
    EXPECT_EQ(info.sampleEnd, 8);
    EXPECT_EQ(info.rays, done.stats.rays);
}

// A scene whose lights are 1e25 times brighter gets a scaled film (fixed_sum.h); the checkpoint
// keeps the scale, and a film of another scale is never merged into.
TEST(Checkpoint, ABrightScenesFilmScaleSurvivesTheCheckpointAndRefusesAnotherScale) {
    SmallRender r;
    for (Light& l : r.scene.lights) l.radiance = l.radiance * 1e25f;
    std::string ckpt = (test::scratchDir() / "bright.ckpt").string();
    LongRenderResult done = r.run(r.options(4), ckpt, false);
    int exponent = done.film.scaleExponent();
    EXPECT_EQ(exponent, filmScaleExponent(r.scene.brightestEmission()));
    EXPECT_GT(exponent, 40);
    EXPECT_EQ(done.stats.nonFiniteSamples, 0u);
    CheckpointInfo info;
    Film back = readCheckpoint(ckpt, info);
    EXPECT_EQ(info.filmScaleExponent, exponent);
    EXPECT_EQ(back.scaleExponent(), exponent);
    EXPECT_EQ(test::filmState(back), test::filmState(done.film));
    EXPECT_EQ(back.pixel(12, 9).x, done.film.pixel(12, 9).x);
    Film unscaled(24, 18, AovRequest::defaults());
    try {
        mergeCheckpoint(ckpt, unscaled, info);
        ADD_FAILURE() << "merged a film of scale 2^" << exponent << " into one of 2^0";
    } catch (const CheckpointError& e) {
        EXPECT_NE(std::string(e.what()).find("scaled by 2^"), std::string::npos) << e.what();
    }
}

TEST(Checkpoint, RefineSixteenToSixtyFourEqualsSixtyFour) {
    SmallRender r;
    auto dir = test::scratchDir();
    for (int adaptive : {0, 4}) {
        // (Not "r" + std::to_string(...): GCC 12's -Wrestrict misfires on it here.)
        std::string ckpt = (dir / fmt::format("r{}.ckpt", adaptive)).string();
        r.run(r.options(16, adaptive), ckpt, false);
        LongRenderResult refined = r.run(r.options(64, adaptive), ckpt, true);
        EXPECT_TRUE(refined.resumed);
        LongRenderResult direct = r.run(r.options(64, adaptive), "", false);
        EXPECT_EQ(test::filmState(refined.film), test::filmState(direct.film)) << adaptive;
        EXPECT_GT(refined.film.totalSamples(), uint64_t(16) * 24 * 18) << adaptive;
    }
}

TEST(Checkpoint, ForeignCorruptedAndTruncatedCheckpointsAreRefused) {
    SmallRender r;
    auto dir = test::scratchDir();
    std::string ckpt = (dir / "a.ckpt").string();
    r.run(r.options(4), ckpt, false);
    // Another depth, seed or size: refused, naming what differs.
    RenderJobOptions deeper = r.options(8);
    deeper.path.maxDepth = 7;
    auto refusedResume = [&](const RenderJobOptions& o, const char* why) {
        try {
            r.run(o, ckpt, true);
            ADD_FAILURE() << "resumed: " << why;
        } catch (const CheckpointError& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    refusedResume(deeper, "max_depth is '5'");
    RenderJobOptions cropped = r.options(8);
    cropped.settings.regionX1 = 12, cropped.settings.regionY1 = 9;
    refusedResume(cropped, "--crop differs");
    refusedResume(r.options(2), "must not shrink");

    std::string bytes = test::readText(ckpt);
    auto refused = [&](const std::string& content, const char* why) {
        std::string bad = (dir / "bad.ckpt").string();
        test::writeFile(bad, content);
        CheckpointInfo info;
        try {
            readCheckpoint(bad, info);
            ADD_FAILURE() << "accepted: " << why;
        } catch (const CheckpointError& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;  // inside the film's sums
    refused(flipped, "checksum mismatch");
    std::string header = bytes;
    header[40] ^= 0x01;
    refused(header, "header is corrupted");
    refused(bytes.substr(0, bytes.size() - 100), "truncated");
    refused(bytes.substr(0, 30), "truncated");
    refused("P3\n1 1\n255\n0 0 0\n", "not a kiln checkpoint");
}

// The kiln command line of the resume tests: a render of about a second on two cores.
constexpr int kSpp = 768;

std::vector<std::string> cliRender(const std::string& out, int spp, bool adaptive) {
    // One thread: long enough on an idle machine for signals and limits to land mid-render.
    std::vector<std::string> a{"render", test::spheres(),     "-r", "64", "48", "-t", "1",
                               "-s",     std::to_string(spp), "-q", "-o", out};
    if (adaptive) a.insert(a.end(), {"-a", "8", "0.02"});
    return a;
}

std::vector<std::string> plus(std::vector<std::string> a, std::vector<std::string> more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
}

// SIGKILL after a random delay (fixed seeds), then --resume until done: the pixels of the
// uninterrupted render, whatever the moment of the kill.
void killAndResume(bool adaptive) {
    auto dir = test::scratchDir();
    std::string ref = (dir / "ref").string();
    ASSERT_EQ(test::runKilnProcess(cliRender(ref, kSpp, adaptive)), 0);
    test::ExrPixels want = test::readExrPixels(ref + ".exr");
    int resumedPartial = 0;
    for (unsigned seed : {1u, 2u, 3u}) {
        std::string out = (dir / ("k" + std::to_string(seed))).string();
        std::vector<std::string> args =
            plus(cliRender(out, kSpp, adaptive), {"--checkpoint-every", "0.03"});
        // Once the first checkpoint is there (the process has started rendering), a random
        // moment of the rest: mid-pixel, mid-wave or mid-checkpoint-write.
        pid_t pid = test::startKiln(args);
        for (int i = 0; i < 400 && !fs::exists(out + ".ckpt"); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::mt19937 rng(seed);
        std::this_thread::sleep_for(
            std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 300)(rng)));
        ::kill(pid, SIGKILL);
        int status = 0;
        ::waitpid(pid, &status, 0);
        if (test::exitCode(status) == 128 + SIGKILL)
            resumedPartial += !readCheckpointInfo(out + ".ckpt").complete;
        ASSERT_EQ(test::runKilnProcess(plus(args, {"--resume"})), 0) << seed;
        EXPECT_TRUE(test::readExrPixels(out + ".exr") == want) << "seed " << seed;
        EXPECT_EQ(test::readText(out + ".png"), test::readText(ref + ".png")) << seed;
    }
    // A kill during a checkpoint write leaves a temporary file; the next run removes it.
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
            << entry.path();
    // At least one kill must have landed mid-render after a checkpoint, or nothing was tested.
    EXPECT_GE(resumedPartial, 1);
}

TEST(Checkpoint, SigkillAtRandomMomentsThenResumeGivesTheSamePixels) { killAndResume(false); }

TEST(Checkpoint, SigkillAtRandomMomentsThenResumeGivesTheSamePixelsAdaptive) {
    killAndResume(true);
}

TEST(Checkpoint, SigtermSavesExits130AndResumes) {
    auto dir = test::scratchDir();
    std::string ref = (dir / "ref").string(), out = (dir / "t").string();
    ASSERT_EQ(test::runKilnProcess(cliRender(ref, kSpp, false)), 0);
    std::vector<std::string> args =
        plus(cliRender(out, kSpp, false), {"--checkpoint-every", "100"});
    pid_t pid = test::startKiln(args);
    ASSERT_TRUE(test::waitForHandler(pid, SIGTERM));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_EQ(test::exitCode(status), 130);
    ASSERT_TRUE(fs::exists(out + ".ckpt"));
    EXPECT_FALSE(readCheckpointInfo(out + ".ckpt").complete);
    EXPECT_TRUE(fs::exists(out + ".exr"));
    EXPECT_EQ(test::runKilnProcess(plus(args, {"--resume"})), 0);
    EXPECT_TRUE(test::readExrPixels(out + ".exr") == test::readExrPixels(ref + ".exr"));
}

TEST(Checkpoint, Sigusr1WritesACheckpointAndTheRenderGoesOn) {
    auto dir = test::scratchDir();
    std::string out = (dir / "u").string();
    std::vector<std::string> args =
        plus(cliRender(out, kSpp, false), {"--checkpoint-every", "100"});
    pid_t pid = test::startKiln(args);
    ASSERT_TRUE(test::waitForHandler(pid, SIGUSR1));
    ::kill(pid, SIGUSR1);
    // The checkpoint appears while the process still runs (its interval alone would not write
    // one before the end).
    bool seen = false, exited = false;
    int status = 0;
    while (!seen && !exited) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        exited = ::waitpid(pid, &status, WNOHANG) == pid;
        seen = !exited && fs::exists(out + ".ckpt");
    }
    if (!exited) ::waitpid(pid, &status, 0);
    EXPECT_TRUE(seen);
    EXPECT_EQ(test::exitCode(status), 0);
    EXPECT_TRUE(readCheckpointInfo(out + ".ckpt").complete);
}

TEST(Checkpoint, TimeLimitStopsWithAValidCheckpointAndExit3) {
    auto dir = test::scratchDir();
    std::string ref = (dir / "ref").string(), out = (dir / "t").string();
    ASSERT_EQ(test::runKilnProcess(cliRender(ref, kSpp, false)), 0);
    std::vector<std::string> args = plus(cliRender(out, kSpp, false), {"--time-limit", "0.3"});
    EXPECT_EQ(test::runKilnProcess(args), 3);
    EXPECT_FALSE(readCheckpointInfo(out + ".ckpt").complete);
    EXPECT_EQ(test::runKilnProcess(plus(cliRender(out, kSpp, false), {"--resume"})), 0);
    EXPECT_TRUE(test::readExrPixels(out + ".exr") == test::readExrPixels(ref + ".exr"));
    EXPECT_TRUE(readCheckpointInfo(out + ".ckpt").complete);
}

// --no-final-checkpoint (a batch frame whose checkpoint would be removed once done): a finished
// whole frame writes none, and its image is the one with a checkpoint; a shard's (sample range or
// crop) is still written, since kiln merge reads it.
TEST(Checkpoint, NoFinalCheckpointLeavesOutOnlyAFinishedWholeFramesOne) {
    auto dir = test::scratchDir();
    auto render = [&](const std::string& name, std::vector<std::string> more) {
        std::vector<std::string> args{
            "render", test::spheres(),       "-r",      "16", "12", "-s", "2", "-q",
            "-o",     (dir / name).string(), "--resume"};
        args.insert(args.end(), more.begin(), more.end());
        EXPECT_EQ(test::runKilnProcess(args), 0) << name;
        return (dir / name).string();
    };
    const std::string kept = render("kept", {});
    const std::string none = render("none", {"--no-final-checkpoint"});
    EXPECT_TRUE(fs::exists(kept + ".ckpt"));
    EXPECT_FALSE(fs::exists(none + ".ckpt"));
    EXPECT_TRUE(test::readExrPixels(kept + ".exr") == test::readExrPixels(none + ".exr"));
    // A checkpoint there before (here a 2-sample one, refined to 4) is stale once the frame is
    // finished: removed, so a later --resume does not redo its samples.
    EXPECT_EQ(test::runKilnProcess({"render", test::spheres(), "-r", "16", "12", "-s", "4", "-q",
                                    "-o", kept, "--resume", "--no-final-checkpoint"}),
              0);
    EXPECT_FALSE(fs::exists(kept + ".ckpt"));
    EXPECT_TRUE(fs::exists(render("range", {"--no-final-checkpoint", "--sample-range", "0", "1"}) +
                           ".ckpt"));
    EXPECT_TRUE(fs::exists(
        render("crop", {"--no-final-checkpoint", "--crop", "0", "0.5", "0", "1"}) + ".ckpt"));
}

TEST(Checkpoint, ResumeWithoutACheckpointStartsAndAForeignOneIsAOneLineExit2) {
    auto dir = test::scratchDir();
    std::string out = (dir / "f").string(), err = (dir / "err.txt").string();
    std::vector<std::string> small{
        "render", test::spheres(), "-r", "16", "12", "-s", "2", "-q", "-o", out};
    EXPECT_EQ(test::runKilnProcess(plus(small, {"--resume"})), 0);
    EXPECT_TRUE(fs::exists(out + ".ckpt"));
    EXPECT_EQ(test::runKilnProcess(plus(small, {"--resume", "--seed", "5"}), -1, 0, err), 2);
    std::string text = test::readText(err);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
    EXPECT_NE(text.find("seed is '0'"), std::string::npos) << text;
    // What the film records differs too: a transparent film's sums are not an opaque one's.
    for (const char* option : {"--transparent", "--sampler"}) {
        std::vector<std::string> other = plus(small, {"--resume", option});
        // The sampler that is not the default (sobol since the estimator measurements).
        if (std::string(option) == "--sampler") other.push_back("independent");
        EXPECT_EQ(test::runKilnProcess(other, -1, 0, err), 2) << option;
        std::string refusal = test::readText(err);
        EXPECT_EQ(std::count(refusal.begin(), refusal.end(), '\n'), 1) << refusal;
    }
}

// A resume refused for what the command line and the scene file decide (another seed, fewer
// samples, an edit of the scene file, a damaged checkpoint) is refused before the scene is loaded:
// no load stage, where a 100M-triangle scene's load, build and probe take a minute. What only the
// loaded scene decides (an edit of a mesh the scene file places) is refused after the load.
TEST(Checkpoint, ARefusalTheCommandLineDecidesComesBeforeTheLoad) {
    auto dir = test::scratchDir();
    const fs::path kiln = dir / "scene.kiln", part = dir / "part.obj";
    const std::string quad = "v -0.5 0.1 -0.5\nv 0.5 0.1 -0.5\nv 0.5 0.1 0.5\nf 1 2 3\n";
    const std::string sceneText = "<kiln-scene><include file=\"" + test::spheres() +
                                  "\"/><mesh file=\"part.obj\"/></kiln-scene>\n";
    std::ofstream(part) << quad;
    std::ofstream(kiln) << sceneText;
    std::string out = (dir / "k").string(), err = (dir / "err.txt").string();
    auto args = [&](const char* spp, std::vector<std::string> extra = {}) {
        return plus({"render", kiln.string(), "-r", "16", "12", "-s", spp, "-o", out, "--resume",
                     "--progress", "json"},
                    extra);
    };
    auto loaded = [&] {
        return test::readText(err).find("\"stage\":\"load\"") != std::string::npos;
    };
    ASSERT_EQ(test::runKilnProcess(args("2"), -1, 0, err), 0) << test::readText(err);
    ASSERT_TRUE(loaded()) << test::readText(err);  // the control: a render that loads says so
    auto refused = [&](const std::vector<std::string>& a, const char* why, bool afterLoad) {
        EXPECT_EQ(test::runKilnProcess(a, -1, 0, err), 2) << why;
        std::string text = test::readText(err);
        EXPECT_NE(text.find(why), std::string::npos) << text;
        EXPECT_EQ(loaded(), afterLoad) << why << ": " << text;
    };
    refused(args("2", {"--seed", "5"}), "seed is '0'", false);
    refused(args("2", {"--microfacet", "ggx"}), "microfacet is", false);
    refused(args("1"), "must not shrink", false);
    refused(args("2", {"-r", "16", "8"}), "resolution is '16x12'", false);
    std::ofstream(kiln) << sceneText << "<!-- edited -->\n";
    refused(args("2"), "scene is", false);
    std::ofstream(kiln) << sceneText;
    std::ofstream(part) << quad << "v 0 0 0\n";
    refused(args("2"), "part.obj", true);
    std::ofstream(part) << quad;
    EXPECT_EQ(test::runKilnProcess(args("4"), -1, 0, err), 0) << test::readText(err);
    const std::string bytes = test::readText(out + ".ckpt");
    std::ofstream(out + ".ckpt", std::ios::binary) << bytes.substr(0, 30);
    refused(args("4"), "truncated", false);
    // A folder where the scene was is the load's own error, not a scene of 0 bytes that differs.
    fs::rename(kiln, dir / "moved.kiln");
    fs::create_directory(kiln);
    refused(args("4"), "is a directory", true);
}

// A .kiln scene's other files (a mesh it places, the .mtl Assimp reads beside that OBJ, a texture,
// the --material-override file) are part of the fingerprint: a resume after an edit of one is
// refused, naming it, not blended into the film.
TEST(Checkpoint, AResumeAfterAnEditOfAFileTheSceneReadsIsRefusedNamingIt) {
    auto dir = test::scratchDir();
    const fs::path mtl = dir / "part.mtl", obj = dir / "part.obj", kiln = dir / "scene.kiln";
    auto write = [](const fs::path& p, const std::string& text) { std::ofstream(p) << text; };
    write(mtl, "newmtl red\nKd 0.8 0.2 0.2\n");
    const std::string quad =
        "mtllib part.mtl\nv -0.5 0.1 -0.5\nv 0.5 0.1 -0.5\nv 0.5 0.1 0.5\nv -0.5 0.1 0.5\n"
        "usemtl red\nf 1 2 3 4\n";
    write(obj, quad);
    fs::copy_file(test::repo("scenes/assets/checker.png"), dir / "tex.png");
    write(kiln, "<kiln-scene><include file=\"" + test::spheres() +
                    "\"/><mesh file=\"part.obj\"/><material name=\"t\" kind=\"principled\" "
                    "base-color-texture=\"tex.png\"/><mesh file=\"part.obj\" material=\"t\" "
                    "translate=\"0 0.2 0\"/></kiln-scene>\n");
    const fs::path override = dir / "override.kiln";
    write(override, "<kiln-scene><material name=\"o\" albedo=\"0.5 0.5 0.5\"/></kiln-scene>\n");
    std::string out = (dir / "k").string(), err = (dir / "err.txt").string();
    std::vector<std::string> args{"render", kiln.string(), "-r",      "16", "12", "-s",      "2",
                                  "-q",     "--log-level", "warning", "-o", out,  "--resume"};
    ASSERT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
    auto refusedNaming = [&](const std::string& file) {
        EXPECT_EQ(test::runKilnProcess(args, -1, 0, err), 2) << file;
        std::string text = test::readText(err);
        EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
        EXPECT_NE(text.find("scene_inputs"), std::string::npos) << text;
        EXPECT_NE(text.find(file), std::string::npos) << text;
    };
    write(mtl, "newmtl red\nKd 0.2 0.8 0.2\n");
    refusedNaming("part.mtl");
    write(mtl, "newmtl red\nKd 0.8 0.2 0.2\n");  // as it was: the checkpoint resumes again
    EXPECT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
    write(obj, quad + "v 0 0 0\n");
    refusedNaming("part.obj");
    write(obj, quad);
    fs::copy_file(test::repo("scenes/assets/maps_half_white.png"), dir / "tex.png",
                  fs::copy_options::overwrite_existing);
    refusedNaming("tex.png");
    // The same render with a material override file: its own checkpoint.
    *std::find(args.begin(), args.end(), out) = out + "-override";
    args.insert(args.end(), {"--material-override", override.string()});
    ASSERT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
    write(override, "<kiln-scene><material name=\"o\" albedo=\"0.9 0.5 0.5\"/></kiln-scene>\n");
    refusedNaming("override.kiln");
    // An override material from a file the override file includes: that file's .mtl counts too.
    write(dir / "ov.mtl", "newmtl blue\nKd 0.2 0.2 0.8\n");
    write(dir / "ov.obj", "mtllib ov.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl blue\nf 1 2 3\n");
    write(dir / "lib.kiln", "<kiln-scene><include file=\"ov.obj\"/></kiln-scene>\n");
    args.back() = (dir / "lib.kiln").string() + ":blue";
    *std::find(args.begin(), args.end(), out + "-override") = out + "-lib";
    ASSERT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
    write(dir / "ov.mtl", "newmtl blue\nKd 0.2 0.8 0.8\n");
    refusedNaming("ov.mtl");
}

// Inputs are named by their path from the scene's folder: two parts' same-named .mtl files with
// their contents swapped are a different scene, and the refusal says which folder's file changed.
TEST(Checkpoint, SameNamedInputsInTwoFoldersAreToldApart) {
    auto dir = test::scratchDir();
    auto write = [](const fs::path& p, const std::string& text) {
        fs::create_directories(p.parent_path());
        std::ofstream(p) << text;
    };
    const std::string red = "newmtl m\nKd 0.8 0.2 0.2\n", blue = "newmtl m\nKd 0.2 0.2 0.8\n";
    const std::string quad =
        "mtllib part.mtl\nv -0.5 0.1 -0.5\nv 0.5 0.1 -0.5\nv 0.5 0.1 0.5\n"
        "v -0.5 0.1 0.5\nusemtl m\nf 1 2 3 4\n";
    for (const char* part : {"a", "b"}) write(dir / part / "part.obj", quad);
    write(dir / "a" / "part.mtl", red);
    write(dir / "b" / "part.mtl", blue);
    write(dir / "scene.kiln", "<kiln-scene><include file=\"" + test::spheres() +
                                  "\"/><mesh file=\"a/part.obj\"/><mesh file=\"b/part.obj\" "
                                  "translate=\"0 0.2 0\"/></kiln-scene>\n");
    std::string out = (dir / "k").string(), err = (dir / "err.txt").string();
    std::vector<std::string> args{
        "render",  (dir / "scene.kiln").string(), "-r", "16", "12", "-s", "2", "-q", "-o", out,
        "--resume"};
    ASSERT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
    write(dir / "a" / "part.mtl", blue);
    write(dir / "b" / "part.mtl", red);
    EXPECT_EQ(test::runKilnProcess(args, -1, 0, err), 2);
    const std::string text = test::readText(err);
    EXPECT_NE(text.find("'a/part.mtl ("), std::string::npos) << text;
    write(dir / "a" / "part.mtl", red);  // as they were: the checkpoint resumes again
    write(dir / "b" / "part.mtl", blue);
    EXPECT_EQ(test::runKilnProcess(args, -1, 0, err), 0) << test::readText(err);
}

// Inside the scene's folder an input is named by its path from there, however the scene wrote
// it; outside, by its filename (its path from the folder would change with the mount's depth).
TEST(Checkpoint, InputsAreNamedFromTheSceneFolderAndOutsideItByFilename) {
    const fs::path dir = test::scratchDir();
    for (const fs::path& p : {dir / "s" / "scene.kiln", dir / "s" / "a" / "part.mtl",
                              dir / "lib" / "deep" / "tex.png"}) {
        fs::create_directories(p.parent_path());
        std::ofstream(p) << p.filename().string();
    }
    fs::create_directories(dir / "s" / "b");  // the OS resolves b/.. before the file
    Scene scene;
    scene.inputFiles = {(dir / "s" / "b" / ".." / "a" / "part.mtl").string(),
                        (dir / "lib" / "deep" / "tex.png").string(),
                        (dir / "s" / "gone.obj").string()};
    const std::string inputs =
        sceneFileIdentity((dir / "s" / "scene.kiln").string(), {}, scene).inputs;
    EXPECT_EQ(inputs.find("a/part.mtl (8 bytes"), 0u) << inputs;
    EXPECT_NE(inputs.find("; tex.png (7 bytes"), std::string::npos) << inputs;
    EXPECT_NE(inputs.find("gone.obj (absent)"), std::string::npos) << inputs;
    EXPECT_EQ(inputs.find(".."), std::string::npos) << inputs;
    EXPECT_EQ(inputs.find("deep"), std::string::npos) << inputs;
}

// The refusal names the file that changed, appeared or went, whichever side lacks the list.
TEST(Checkpoint, ARefusalNamesTheOneInputThatDiffers) {
    const std::string mtl = "part.mtl (26 bytes, crc32 85daacc2)",
                      mtl2 = "part.mtl (26 bytes, crc32 33631f6d)",
                      obj = "part.obj (9 bytes, crc32 1)", png = "a.png (absent)";
    auto differ = [](const std::string& saved, const std::string& here) {
        auto with = [](const std::string& inputs) {
            Fingerprint f{{"scene", "s.kiln (1 bytes, crc32 0)"}};
            if (!inputs.empty()) f.emplace_back("scene_inputs", inputs);
            return f;
        };
        return fingerprintDifference(with(saved), with(here), "k.ckpt");
    };
    EXPECT_EQ(differ(mtl + "; " + obj, mtl + "; " + obj), "");
    EXPECT_EQ(differ(mtl + "; " + obj, mtl2 + "; " + obj),
              "scene_inputs: '" + mtl + "' in k.ckpt, '" + mtl2 + "' here");
    // a.png sorts first: the edited .mtl is named, not the file in its place in the list
    EXPECT_EQ(differ(mtl + "; " + obj, png + "; " + mtl2 + "; " + obj),
              "scene_inputs: '" + mtl + "' in k.ckpt, '" + mtl2 + "' here");
    EXPECT_EQ(differ(mtl + "; " + obj, png + "; " + mtl + "; " + obj),
              "scene_inputs: no file a.png in k.ckpt, '" + png + "' here");
    EXPECT_EQ(differ(png + "; " + mtl, mtl),
              "scene_inputs: '" + png + "' in k.ckpt, no file a.png here");
    // A checkpoint without the list (a one-file scene's) and a scene with one, and the reverse.
    EXPECT_EQ(differ("", obj), "scene_inputs: no file part.obj in k.ckpt, '" + obj + "' here");
    EXPECT_EQ(differ(obj, ""), "scene_inputs: '" + obj + "' in k.ckpt, no file part.obj here");
    Fingerprint a{{"scene", "x"}, {"extra", "1"}}, b{{"scene", "x"}};
    EXPECT_EQ(fingerprintDifference(a, b, "k.ckpt"), "extra is '1' in k.ckpt, absent here");
    EXPECT_EQ(fingerprintDifference(b, a, "k.ckpt"), "extra is absent in k.ckpt, '1' here");
}

// A scene read from its one file keeps the fingerprint it had before other files were named.
TEST(Checkpoint, AOneFileScenesFingerprintNamesNoOtherInputs) {
    SmallRender r;
    RenderJob job(r.scene, *r.accel, r.options(1));
    for (const auto& [key, value] : checkpointFingerprint(job, test::spheres(), {}))
        EXPECT_NE(key, "scene_inputs") << value;
}

// A small tmpfs for the duration of a test (root only: CI runs as root), unmounted however the
// test ends.
struct ScopedTmpfs {
    fs::path dir;
    bool mounted = false;
    ScopedTmpfs(fs::path where, const std::string& options) : dir(std::move(where)) {
        fs::create_directories(dir);
        mounted = ::mount("tmpfs", dir.c_str(), "tmpfs", 0, options.c_str()) == 0;
    }
    ~ScopedTmpfs() {
        if (mounted) ::umount2(dir.c_str(), MNT_DETACH);
    }
};

// Fills the filesystem of dir to the last byte.
void fillDisk(const fs::path& dir) {
    std::ofstream filler(dir / "filler", std::ios::binary);
    std::string block(1 << 16, 'x');
    while (filler.write(block.data(), std::streamsize(block.size()))) {
    }
}

TEST(Checkpoint, DiskFullDuringACheckpointKeepsThePreviousOneAndReportsTheFailure) {
    if (::geteuid() != 0) GTEST_SKIP() << "mounting a tmpfs needs root (CI runs as root)";
    fs::path scratch = test::scratchDir();
    ScopedTmpfs disk(scratch / "disk", "size=2m");
    ASSERT_TRUE(disk.mounted);
    SmallRender r;
    std::string ckpt = (disk.dir / "a.ckpt").string();
    LongRenderResult first = r.run(r.options(4), ckpt, false);
    std::string before = test::readText(ckpt);
    std::string png = (disk.dir / "a.png").string();
    writePreview(png, first.film);
    std::string pngBefore = test::readText(png);
    // The film's EXR likewise keeps the previous file.
    std::string exr = (disk.dir / "a.exr").string();
    ExrOptions zips;
    zips.compression = ExrCompression::Zips;
    writeExr(exr, first.film, {}, zips);
    std::string exrBefore = test::readText(exr);
    fillDisk(disk.dir);
    EXPECT_THROW(r.run(r.options(8), ckpt, true), std::runtime_error);
    EXPECT_THROW(writePreview(png, first.film), std::runtime_error);
    EXPECT_THROW(writeExr(exr, first.film, {}, zips), std::runtime_error);
    EXPECT_EQ(test::readText(ckpt), before);  // still the valid previous checkpoint
    EXPECT_EQ(test::readText(png), pngBefore);
    EXPECT_EQ(test::readText(exr), exrBefore);
    CheckpointInfo info;
    EXPECT_EQ(test::filmState(readCheckpoint(ckpt, info)), test::filmState(first.film));
    for (const auto& entry : fs::directory_iterator(disk.dir))  // no temporary file left
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
    // The command line finds the full disk before rendering: exit 2, one line.
    std::string err = (scratch / "err.txt").string();
    EXPECT_EQ(test::runKilnProcess({"render", test::spheres(), "-r", "64", "48", "-q", "-o",
                                    (disk.dir / "b").string()},
                                   -1, 0, err),
              2);
    EXPECT_NE(test::readText(err).find("free"), std::string::npos) << test::readText(err);
    // A read-only filesystem likewise, and its message says so.
    ASSERT_EQ(::mount("tmpfs", disk.dir.c_str(), "tmpfs", MS_REMOUNT | MS_RDONLY, "size=2m"), 0);
    EXPECT_EQ(test::runKilnProcess({"render", test::spheres(), "-r", "8", "6", "-q", "-o",
                                    (disk.dir / "c").string()},
                                   -1, 0, err),
              2);
    EXPECT_NE(test::readText(err).find("not writable"), std::string::npos) << test::readText(err);
}

// An EXR whose last bytes sit in the stream's buffer until the file is closed: a failure of that
// last write (here the file-size limit) is an error, and nothing is renamed into place (OpenEXR's
// OutputFile writes its line offsets in its destructor and drops any error there: a render exited 0
// with a truncated EXR).
TEST(Checkpoint, AnExrCutShortAtItsLastWriteIsAnError) {
    fs::path dir = test::scratchDir();
    const std::string out = (dir / "cut").string();
    test::CliRun r = test::runProgram("trap '' XFSZ; ulimit -f 3; " + std::string(KILN_BINARY),
                                      "render " + test::repo("scenes/cornell.dae") +
                                          " -r 8 8 -s 1 -q --compression zips -o " + out);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("cut.exr: cannot write EXR"), std::string::npos) << r.err;
    // The summary names what was written: the preview, not the EXR.
    EXPECT_NE(r.err.find("-> " + out + ".png\n"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out + ".exr"));
    for (const auto& entry : fs::directory_iterator(dir))  // no temporary file left
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

// Issue #33 item 5: a finished render whose final checkpoint does not fit the disk keeps its image.
// The disk is filled while the render runs (after kiln's free-space check), leaving room for the
// EXR and PNG but not for the checkpoint: the images are written first, the failed checkpoint is a
// warning (in the JSON result too) and the exit code is 0.
TEST(Checkpoint, AFinalCheckpointThatDoesNotFitLeavesTheFinishedImageAndAWarning) {
    if (::geteuid() != 0) GTEST_SKIP() << "mounting a tmpfs needs root (CI runs as root)";
    fs::path scratch = test::scratchDir();
    ScopedTmpfs disk(scratch / "disk", "size=8m");
    ASSERT_TRUE(disk.mounted);
    std::string base = (disk.dir / "a").string(), err = (scratch / "err.txt").string(),
                out = (scratch / "out.json").string();
    // 64x48 with the default AOVs: a 1.0 MiB checkpoint, an EXR of about 0.3 MiB.
    pid_t pid =
        test::startKiln({"render", test::spheres(), "-r", "64", "48", "-s", "512", "-t", "1",
                         "--checkpoint-every", "600", "--json", "--progress", "none", "-o", base},
                        err, out);
    ASSERT_TRUE(test::waitForHandler(pid, SIGUSR1));
    ::kill(pid, SIGUSR1);  // a checkpoint at the first pixel: the render is under way
    bool started = false;
    for (int i = 0; i < 4000 && !started; ++i) {
        started = fs::exists(base + ".ckpt");
        if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(started) << test::readText(err);
    ::kill(pid, SIGSTOP);
    uintmax_t checkpointBytes = fs::file_size(base + ".ckpt");
    fillDisk(disk.dir);
    fs::resize_file(disk.dir / "filler", fs::file_size(disk.dir / "filler") - (600 << 10));
    ::kill(pid, SIGCONT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    std::string log = test::readText(err);
    ASSERT_EQ(test::exitCode(status), 0) << log;
    EXPECT_GT(checkpointBytes, uintmax_t(600 << 10));
    // The finished image is there and whole.
    test::ExrPixels pixels = test::readExrPixels(base + ".exr");
    EXPECT_EQ(pixels.values.size() % (64 * 48), 0u);
    EXPECT_FALSE(pixels.values.empty());
    EXPECT_GT(fs::file_size(base + ".png"), 0u);
    // The checkpoint on disk is still the earlier valid one, and the result says what failed.
    CheckpointInfo info = readCheckpointInfo(base + ".ckpt");
    EXPECT_FALSE(info.complete);
    nlohmann::json result = nlohmann::json::parse(test::readText(out));
    std::string warnings = result["warnings"].dump();
    EXPECT_NE(warnings.find("a.ckpt"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("the finished image is written"), std::string::npos) << warnings;
    EXPECT_NE(log.find("warning"), std::string::npos) << log;
}

TEST(AtomicFile, TwoWritersOfOneTargetNeverShareATemporaryFile) {
    auto dir = test::scratchDir();
    std::string target = (dir / "out.bin").string();
    AtomicFile a(target), b(target);
    EXPECT_NE(a.tempPath(), b.tempPath());
    a.write("first", 5);
    b.write("second", 6);
    b.commit();
    EXPECT_EQ(test::readText(target), "second");
    a.commit();
    EXPECT_EQ(test::readText(target), "first");
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file();
    EXPECT_EQ(files, 1);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

TEST(AtomicFile, TemporariesOfAKilledProcessAreRemovedALiveOnesKept) {
    auto dir = test::scratchDir();
    std::string target = (dir / "out.ckpt").string();
    pid_t child = ::fork();
    if (child == 0) {
        AtomicFile left(target);
        left.write("partial", 7);
        ::_exit(0);  // as a SIGKILL would: no destructor, the temporary file stays
    }
    ::waitpid(child, nullptr, 0);
    AtomicFile mine(target);  // this live process's write in progress
    auto temporaries = [&] {
        int n = 0;
        for (const auto& entry : std::filesystem::directory_iterator(dir))
            n += entry.path().filename().string().find(".tmp-") != std::string::npos;
        return n;
    };
    EXPECT_EQ(temporaries(), 2);
    EXPECT_EQ(removeStaleTemporaries(target), 1);
    EXPECT_EQ(temporaries(), 1);
    EXPECT_TRUE(std::filesystem::exists(mine.tempPath()));
}

// A frame's outputs in one directory read once: each path's own stale temporaries are counted to
// it, another path's (a name that begins with the first's) are not.
TEST(AtomicFile, SeveralPathsInOneDirectoryEachRemoveTheirOwn) {
    auto dir = test::scratchDir();
    const std::vector<std::string> paths{(dir / "f.exr").string(), (dir / "f.exr.ckpt").string(),
                                         (dir / "f.png").string()};
    pid_t child = ::fork();
    if (child == 0) {
        for (const std::string& path : {paths[0], paths[1], paths[1]})
            (new AtomicFile(path))->write("partial", 7);  // never destroyed
        ::_exit(0);  // as a SIGKILL would: the temporary files stay
    }
    ::waitpid(child, nullptr, 0);
    EXPECT_EQ(removeStaleTemporaries(paths), (std::vector<int>{1, 2, 0}));
    EXPECT_EQ(removeStaleTemporaries(paths), (std::vector<int>{0, 0, 0}));
}

}  // namespace
}  // namespace kiln
