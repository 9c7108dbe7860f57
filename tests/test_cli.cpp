// The kiln executable end to end: help, bad flags, bad files, outputs and exit codes.
#include <OpenImageIO/imageio.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <thread>

#include "kiln_run.h"
#include "long_render_support.h"
#include "test_support.h"

namespace kiln {
namespace {

using test::CliRun;
using test::runKiln;

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// A tiny render of scene with one bad option: exit code 2 and a one-line error.
void expectOneLineRefusal(const std::string& scene, const std::filesystem::path& dir,
                          const std::string& bad) {
    CliRun r = runKiln("render " + scene + " -r 8 8 -q -o " + (dir / "bad").string() + " " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_EQ(lines(r.err), 1) << bad << ": " << r.err;
}

TEST(Cli, HelpDocumentsEveryCommandAndOption) {
    CliRun top = runKiln("--help");
    EXPECT_EQ(top.code, 0);
    for (const char* cmd : {"render", "info", "crosscheck", "bench"})
        EXPECT_NE(top.out.find(cmd), std::string::npos);
    CliRun render = runKiln("render --help");
    EXPECT_EQ(render.code, 0);
    for (const char* opt : {"-s, --spp", "-t, --threads", "-r, --resolution", "-f, --file",
                            "--accel", "--integrator", "--camera", "--env"})
        EXPECT_NE(render.out.find(opt), std::string::npos) << opt;
    EXPECT_EQ(runKiln("info --help").code, 0);
    EXPECT_EQ(runKiln("crosscheck --help").code, 0);
    EXPECT_EQ(runKiln("bench accel --help").code, 0);
}

TEST(Cli, BadFlagsAreOneLineErrorsWithExitCode2) {
    for (const char* args :
         {"render --bogus scene.dae", "render -s abc x.dae", "render -s 0 x.dae", "render -r 10",
          "render --accel gpu x.dae", "frobnicate", "info", "render a.dae b.dae"}) {
        CliRun r = runKiln(args);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_GE(lines(r.err), 1) << args;
        EXPECT_NE(r.err.find("kiln"), std::string::npos) << args;
    }
    EXPECT_EQ(lines(runKiln("render --bogus x").err), 1);
}

TEST(Cli, BadSceneIsOneLineNamingTheFile) {
    CliRun r = runKiln("render /nonexistent/scene.dae");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(lines(r.err), 1);
    EXPECT_NE(r.err.find("/nonexistent/scene.dae: no such file"), std::string::npos) << r.err;
    CliRun unknown = runKiln("render " + test::repo("scenes/cornell.dae") +
                             " --integrator magic -r 8 8 -o /tmp/kiln-tests/x");
    EXPECT_EQ(unknown.code, 2);
    EXPECT_NE(unknown.err.find("unknown integrator"), std::string::npos);
}

TEST(Cli, RenderWritesExrAndPngAndReportsStats) {
    auto dir = test::scratchDir();
    CliRun r = runKiln("render " + test::repo("scenes/cornell.dae") + " -r 64 48 -s 2 -q -o " +
                       (dir / "box").string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "box.exr"));
    EXPECT_TRUE(std::filesystem::exists(dir / "box.png"));
    EXPECT_NE(r.err.find("Mrays/s"), std::string::npos);
    EXPECT_NE(r.err.find("load"), std::string::npos);
    // The CS184 form: -f names the PNG, the EXR goes beside it.
    CliRun f = runKiln("render " + test::repo("scenes/cornell.dae") + " -r 32 24 -q -t 1 -f " +
                       (dir / "cs.png").string());
    ASSERT_EQ(f.code, 0) << f.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "cs.png"));
    EXPECT_TRUE(std::filesystem::exists(dir / "cs.exr"));
}

TEST(Cli, TraversalFloorReportsTheRendersRaysOrRefusesBeforeRecordingTooMany) {
    auto dir = test::scratchDir();
    std::string render = "render " + test::repo("scenes/cornell.dae") + " -r 32 24 -s 64 -q -o " +
                         (dir / "floor").string() + " --traversal-floor";
    CliRun r = runKiln(render);
    ASSERT_EQ(r.code, 0) << r.err;
    // The floor names the render's own ray count.
    size_t at = r.err.find(" samples, ");
    ASSERT_NE(at, std::string::npos) << r.err;
    std::string rays = r.err.substr(at + 10, r.err.find(" rays", at) - at - 10);
    EXPECT_NE(r.err.find("the render's " + rays + " rays traced again alone"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("occlusion, batched"), std::string::npos) << r.err;
    // Too little memory to record them (2 MB: enough for the film and the EXR write, checked
    // before the render, not for the rays): the image is still written, then a one-line error.
    std::filesystem::remove(dir / "floor.exr");
    CliRun small = [&] {
        test::ScopedMemoryLimit limit("2000000");
        return runKiln(render);
    }();
    EXPECT_EQ(small.code, 2) << small.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "floor.exr"));
    EXPECT_NE(small.err.find("--traversal-floor: recording the render's " + rays + " rays needs"),
              std::string::npos)
        << small.err;
    EXPECT_EQ(small.err.find("traced again alone"), std::string::npos);
}

TEST(Cli, OutputOptions) {
    auto dir = test::scratchDir();
    std::string scene = test::repo("scenes/cornell.dae");
    for (const char* bad :
         {"--aov sparkle", "--view Filmic", "--display P3", "--compression lzma"}) {
        expectOneLineRefusal(scene, dir, bad);
        EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr")) << bad;  // refused before rendering
    }
    CliRun ok = runKiln("render " + scene +
                        " -r 16 12 -s 32 -a 8 0.1 -q --half --compression piz --aov all "
                        "--view 'ACES 1.0 SDR-video' -o " +
                        (dir / "full").string());
    ASSERT_EQ(ok.code, 0) << ok.err;
    for (const char* f : {"full.exr", "full.png", "full.samples.png"})
        EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
    CliRun info = runKiln("render " + test::shared("meshes/stanford-bunny.obj") + " --env " +
                          test::shared("envmaps/studio.exr") + " -r 16 12 -s 2 -q -o " +
                          (dir / "env").string());
    EXPECT_EQ(info.code, 0) << info.err;
}

TEST(Cli, PlanIsPrintedRecordedAndOverridable) {
    auto dir = test::scratchDir();
    CliRun info = runKiln("info " + test::cs184("meshedit/cow.dae"));
    EXPECT_NE(info.out.find("render plan (diffuse-only,delta-lights-only)"), std::string::npos)
        << info.out;
    CliRun hemi = runKiln("render " + test::cs184("meshedit/cow.dae") + " -H -r 8 6 -q -o " +
                          (dir / "h").string());
    EXPECT_EQ(hemi.code, 0);
    EXPECT_NE(hemi.err.find("hemisphere sampling cannot see"), std::string::npos) << hemi.err;
    CliRun general = runKiln("render " + test::cs184("meshedit/cow.dae") +
                             " --plan general -r 8 6 -q -o " + (dir / "g").string());
    EXPECT_EQ(general.code, 0) << general.err;
    CliRun header = runKiln("render " + test::cs184("sky/CBspheres.dae") + " -r 8 6 -q -o " +
                            (dir / "p").string());
    ASSERT_EQ(header.code, 0);
    EXPECT_EQ(std::system(("oiiotool --info -v " + (dir / "p.exr").string() +
                           " | grep -q 'kiln:plan: \"delta-specular'")
                              .c_str()),
              0);
    EXPECT_EQ(runKiln("render x.dae --plan fastest").code, 2);
}

TEST(Cli, CropRendersExactlyThosePixelsOfTheWholeImage) {
    // The course's 480x360 view is the central 60 % of its 800x600 one: --crop 0.2 0.8 0.2 0.8.
    auto dir = test::scratchDir();
    std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    std::string common = " -r 40 30 -s 3 -m 3 -q --aov none -t 2 ";
    ASSERT_EQ(runKiln("render " + scene + common + "-o " + (dir / "whole").string()).code, 0);
    CliRun crop = runKiln("render " + scene + common + "--crop 0.2 0.8 0.2 0.8 -o " +
                          (dir / "crop").string());
    ASSERT_EQ(crop.code, 0) << crop.err;
    auto read = [](const std::filesystem::path& p, OIIO::ImageSpec& spec) {
        auto in = OIIO::ImageInput::open(p.string());
        EXPECT_TRUE(in) << p;
        spec = in->spec();
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
        return px;
    };
    OIIO::ImageSpec ws, cs;
    std::vector<float> whole = read(dir / "whole.exr", ws), part = read(dir / "crop.exr", cs);
    // pbrt's rule: ceil(0.2 * 40) = 8 .. ceil(0.8 * 40) = 32; ceil(6) = 6 .. ceil(24) = 24.
    EXPECT_EQ(cs.width, 24);
    EXPECT_EQ(cs.height, 18);
    EXPECT_EQ(cs.x, 8);
    EXPECT_EQ(cs.y, 6);
    EXPECT_EQ(cs.full_width, 40);
    EXPECT_EQ(cs.full_height, 30);
    int nc = ws.nchannels;
    ASSERT_EQ(cs.nchannels, nc);
    int differ = 0;
    for (int y = 0; y < cs.height; ++y)
        for (int x = 0; x < cs.width; ++x)
            for (int c = 0; c < nc; ++c)
                differ += part[(size_t(y) * cs.width + x) * nc + c] !=
                          whole[(size_t(y + 6) * ws.width + x + 8) * nc + c];
    EXPECT_EQ(differ, 0) << "a cropped pixel must be the same sample for sample";
    for (const char* bad :
         {"--crop 0.5 0.5 0 1", "--crop 0 1 -0.1 1", "--crop 0 1 0 x", "--crop 0 1.5 0 1"}) {
        expectOneLineRefusal(scene, dir, bad);
    }
}

TEST(Cli, InfoJsonAndCrosscheck) {
    CliRun info = runKiln("info --json " + test::cs184("sky/CBspheres.dae"));
    EXPECT_EQ(info.code, 0);
    EXPECT_NE(info.out.find("\"spheres\": 2"), std::string::npos);
    CliRun cc = runKiln("crosscheck " + test::cs184("sky/CBspheres.dae") + " --rays 8000");
    EXPECT_EQ(cc.code, 0) << cc.out << cc.err;
    EXPECT_NE(cc.out.find("shadow"), std::string::npos);
    CliRun json = runKiln("crosscheck " + test::cs184("sky/CBspheres.dae") + " --rays 4000 --json");
    EXPECT_NE(json.out.find("\"genuine\": 0"), std::string::npos) << json.out;
}

TEST(Cli, SigintWritesThePartialImageAndExitsNonZero) {
    auto dir = test::scratchDir();
    std::string out = (dir / "partial").string();
    pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::freopen("/dev/null", "w", stderr);
        ::execl(KILN_BINARY, KILN_BINARY, "render", test::cs184("sky/CBbunny.dae").c_str(),
                "--accel", "reference", "-r", "400", "300", "-s", "100000", "-q", "-o", out.c_str(),
                (char*)nullptr);
        ::_exit(127);
    }
    // Wait until kiln catches SIGINT (a loaded machine may take seconds to start it), then let it
    // render a moment and interrupt.
    ASSERT_TRUE(test::waitForHandler(pid, SIGINT));
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_TRUE(std::filesystem::exists(out + ".exr"));
    EXPECT_TRUE(std::filesystem::exists(out + ".png"));
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// Flags the command line alone decides are refused before the scene is read: with a broken scene
// the flag is what the error names (at 100M triangles the load, build and plan take a minute).
TEST(Cli, FlagMistakesAreRefusedBeforeTheScene) {
    auto dir = test::scratchDir();
    const std::string broken =
        test::writeFile(dir / "broken.ply", "ply\nformat ascii 1.0\nend_header\n");
    EXPECT_NE(runKiln("render " + broken + " -q -o " + (dir / "x").string()).err.find("broken.ply"),
              std::string::npos);  // the control: the scene alone is refused
    for (auto [flags, what] : {
             std::pair{"-r 64 48 --pixel 100 10 --sample 0", "--pixel is outside the 64x48 image"},
             std::pair{"--position 0 0 5 --look-at 0 0 0 --up 0 0 1", "parallel to the view"},
         }) {
        CliRun r = runKiln("render " + broken + " -q -o " + (dir / "x").string() + " " + flags);
        EXPECT_EQ(r.code, 2) << flags;
        EXPECT_EQ(lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    }
}

TEST(Cli, AnImageTooBigForMemoryIsRefusedBeforeLoading) {
    // 8000x6000 with the default AOVs under a 4 GiB limit: one line naming the size and what is
    // available, exit 2, no output file and no bad_alloc.
    auto dir = test::scratchDir();
    test::ScopedMemoryLimit limit("4294967296");
    CliRun r = runKiln("render " + test::repo("scenes/cornell.dae") + " -r 8000 6000 -q -o " +
                       (dir / "big").string());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("MiB available"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "big.exr"));
}

}  // namespace
}  // namespace kiln
