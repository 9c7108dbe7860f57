// Input a review found crashing, hanging or lost: each is now one line and exit 2 before the work
// (or, for the checkpoint period, a render that finishes).
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::runKiln;

std::string scene() { return test::cs184("sky/CBspheres_lambertian.dae"); }

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

void expectRefused(const std::string& args, const std::string& what) {
    CliRun r = runKiln(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << args << "\n" << r.err;
}

// A camera put beyond the span kiln traces made Embree assert (SIGABRT) on the rays.
TEST(CliHostile, ACameraBeyondTheTracedSpanIsRefused) {
    auto dir = test::scratchDir();
    const std::string render = "render " + scene() + " -r 16 12 -s 1 -q -o " + (dir / "x").string();
    expectRefused(render + " --position 1e19 0 0", "--position takes coordinates within");
    expectRefused(render + " --turntable 4 --frame 1 --orbit-centre 1e19 0 0",
                  "--orbit-centre takes coordinates within");
    EXPECT_EQ(runKiln(render + " --up 1e30 1e30 0").code, 0);  // a direction: only its way counts
}

TEST(CliHostile, AReplayedRayMustBeOneEmbreeTakes) {
    for (const char* ray : {"nan nan nan nan nan nan nan nan", "0 0 0 1 0 0 0 1 junk",
                            "0 0 0 0 0 0 0 1", "0 0 0 1 0 0 2 1"})
        expectRefused("crosscheck " + scene() + " --replay '" + ray + "'", "--replay needs 8");
    expectRefused("crosscheck " + scene() + " --replay '1e19 0 0 1 0 0 0 1'",
                  "beyond the span kiln traces");
    EXPECT_EQ(runKiln("crosscheck " + scene() + " --replay '0 0 0 1 0 0 0 inf'").code, 0);
}

// '{frame:-4}' made fmt pad the name to 4e9 characters: the batch hung eating memory.
TEST(CliHostile, AnOutputPatternsWidthIsDigitsUpToTwelve) {
    auto dir = test::scratchDir();
    for (auto [pattern, what] :
         {std::pair{"{frame:-4}", "the width is a number of digits"},
          std::pair{"{frame:abc}", "the width is a number of digits"},
          std::pair{"{frame:13}", "the width is a number of digits"},
          std::pair{"{frame:0013}", "the width is a number of digits"},
          std::pair{"{scene:04}", "only {frame} and {index} take a width"}}) {
        const std::string job = test::writeFile(
            dir / "job.json", R"({"output": "o/)" + std::string(pattern) + R"(", "scenes": [")" +
                                  scene() + R"("], "cameras": [{"name": "a", "turntable": 2}]})");
        expectRefused("batch " + job + " --dry-run", what);
    }
    for (const char* pattern : {"{frame:012}", "{frame:004}", "{frame:}", "{frame:12}"}) {
        const std::string job = test::writeFile(
            dir / "job.json", R"({"output": "o/)" + std::string(pattern) + R"(", "scenes": [")" +
                                  scene() + R"("], "cameras": [{"name": "a", "turntable": 2}]})");
        EXPECT_EQ(runKiln("batch " + job + " --dry-run").code, 0) << pattern;
    }
}

// Every tile paused before its first pixel when the period was shorter than a write: the render
// wrote checkpoints without end.
TEST(CliHostile, ACheckpointPeriodShorterThanAWriteStillRenders) {
    auto dir = test::scratchDir();
    CliRun r = runKiln("render " + scene() + " -r 32 24 -s 16 -t 2 -q -o " + (dir / "x").string() +
                       " --checkpoint-every 1e-6");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("12288 samples"), std::string::npos) << r.err;
}

// Opening a FIFO blocks until a writer comes, and a signal did not end the wait.
TEST(CliHostile, AFifoIsNotASceneNorAnEnvironmentMap) {
    auto dir = test::scratchDir();
    ASSERT_EQ(::mkfifo((dir / "fifo.obj").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
    const std::string out = " -r 16 12 -s 1 -q -o " + (dir / "x").string();
    expectRefused("render " + (dir / "fifo.obj").string() + out, "is not a regular file");
    const std::string including = test::writeFile(
        dir / "inc.kiln", "<kiln-scene><include file=\"fifo.obj\"/></kiln-scene>\n");
    expectRefused("render " + including + out, "is not a regular file");
    expectRefused("render " + scene() + " -e " + (dir / "fifo.exr").string() + out,
                  "is not a regular file");
    // A texture is something the importer cannot honour: a warning, the plain colour.
    ASSERT_EQ(::mkfifo((dir / "fifo.png").c_str(), 0600), 0);
    test::writeFile(dir / "t.mtl", "newmtl m\nKd 1 1 1\nmap_Kd fifo.png\n");
    const std::string textured = test::writeFile(dir / "t.obj",
                                                 "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 "
                                                 "0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n");
    CliRun r = runKiln("render " + textured + out);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("fifo.png is not a regular file"), std::string::npos) << r.err;
}

// A name the file system refuses was exit 1 with the library's text; a directory as an output
// was found only after the merge or denoise; "dir/" wrote the hidden dir/.exr.
TEST(CliHostile, OutputsThatCannotBeWrittenAreRefusedBeforeTheWork) {
    auto dir = test::scratchDir();
    const std::string render = "render " + scene() + " -r 16 12 -s 2 -q";
    expectRefused(render + " -o " + (dir / std::string(240, 'y')).string(), "File name too long");
    expectRefused(render + " -o " + (dir / "sub").string() + "/", "names a directory");
    const std::string shard = (dir / "s0").string();
    ASSERT_EQ(runKiln(render + " -o " + shard + " --sample-range 0 1").code, 0);
    fs::create_directory(dir / "taken.exr");
    expectRefused("merge " + shard + ".ckpt -o " + (dir / "taken").string(), "is a directory");
    expectRefused("denoise " + shard + ".exr -o " + (dir / "taken.exr").string(), "is a directory");
}

TEST(CliHostile, SubdivideNeverWritesOverItsInput) {
    auto dir = test::scratchDir();
    const std::string mesh =
        test::writeFile(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expectRefused("tools subdivide " + mesh + " " + mesh, "OUT is IN");
    expectRefused("tools subdivide " + mesh + " " + (dir / "out.stl").string(), ".ply or .obj");
    EXPECT_EQ(runKiln("tools subdivide " + mesh + " " + (dir / "OUT.OBJ").string()).code, 0);
    std::ifstream obj(dir / "OUT.OBJ");
    EXPECT_EQ(obj.get(), 'v');  // written as OBJ, not PLY
    std::ifstream kept(dir / "tri.obj");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}),
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

// A bad later render failed after the earlier ones had rendered; two renders with one -o
// overwrote each other.
TEST(CliHostile, RenderFramesChecksEveryRenderFirst) {
    auto dir = test::scratchDir();
    const std::string a = (dir / "a").string();
    expectRefused("render-frames " + scene() + " -r 16 12 -s 1 -q -o " + a + " --then " + scene() +
                      " -s 0 -o " + (dir / "b").string(),
                  "render 2 of 2: option --spp");
    EXPECT_FALSE(fs::exists(a + ".exr"));
    expectRefused("render-frames " + scene() + " -r 16 12 -s 1 -q -o " + a + " --then " + scene() +
                      " -r 16 12 -s 1 -q -o " + a,
                  "renders 1 and 2 of 2 both write");
    expectRefused("render-frames " + scene() + " -r 16 12 -s 1 -q -o " + a + " --then " + scene() +
                      " -r 16 12 -s 1 -q -o " + a + ".exr",
                  "renders 1 and 2 of 2 both write");
    const std::string first = "render-frames " + scene() + " -r 16 12 -s 1 -q -o " + a;
    expectRefused(
        first + " --heatmap --then " + scene() + " -r 16 12 -s 1 -q -o " + a + ".samples.png",
        "renders 1 and 2 of 2 both write");
    expectRefused(first + " --then " + scene() + " -r 16 12 -s 1 -q",
                  "render 2 of 2: every render of kiln render-frames needs -o");
    expectRefused(
        first + " --then " + scene() + " -r 16 12 -s 1 -q -o " + (dir / "nodir" / "b").string(),
        "render 2 of 2: output directory");
    EXPECT_FALSE(fs::exists(a + ".exr"));
}

// NaN, infinite and negative texels are set to 0 as before, and now said so.
TEST(CliHostile, AnEnvironmentMapsBadTexelsAreCountedInAWarning) {
    auto dir = test::scratchDir();
    const std::string map = (dir / "nan.exr").string();
    ASSERT_EQ(test::runProgram("oiiotool",
                               "--create 4x2 3 --fill:color=-1,-1,-1 4x2 --powc 0.5 "
                               "-d float -o " +
                                   map)
                  .code,
              0);
    CliRun r =
        runKiln("render " + scene() + " -e " + map + " -r 16 12 -s 1 -o " + (dir / "x").string());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("8 of 8 texels NaN or infinite (set to 0)"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// A newline in a file name split the one-line error in two.
TEST(CliHostile, AnErrorNamingAFileWithANewlineIsOneLine) {
    CliRun r = runKiln("render " + test::shellQuoted("/nonexistent/no\nsuch.dae") + " -q");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("no\\nsuch.dae: no such file"), std::string::npos) << r.err;
}

// A resume refused for other AOVs named them by a bit mask.
TEST(CliHostile, AResumeRefusedForOtherAovsNamesThem) {
    auto dir = test::scratchDir();
    const std::string render =
        "render " + scene() + " -r 16 12 -q -o " + (dir / "x").string() + " --sample-range 0 1 ";
    ASSERT_EQ(runKiln(render + "-s 2 --aov direct,N").code, 0);
    CliRun r = runKiln(render + "-s 2 --aov none --resume");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("direct,N bounces"), std::string::npos) << r.err;
}

TEST(CliHostile, AJobsArgsNameNoOutputAndKeepLargeNumbers) {
    auto dir = test::scratchDir();
    auto job = [&](const std::string& args) {
        return test::writeFile(dir / "job.json", R"({"output": "o/{scene}", "scenes": [")" +
                                                     scene() + R"("], "args": [)" + args + "]}");
    };
    expectRefused("batch " + job(R"("-r", 16, 12, "--output", "elsewhere")") + " --dry-run",
                  "'--output' names the output");
    expectRefused("batch " + job(R"("-o", "elsewhere")") + " --dry-run", "'-o' names the output");
    EXPECT_EQ(runKiln("batch " + job(R"("-r", 16, 12, "-o", 1)") + " --dry-run").code, 0);
    expectRefused("batch " + job(R"("-s", 18446744073709551615)") + " --dry-run",
                  "got '18446744073709551615'");
}

TEST(CliHostile, OptionsThatWouldDoNothingAreWarnedOf) {
    auto dir = test::scratchDir();
    const std::string render = "render " + scene() + " -r 16 12 -o " + (dir / "x").string();
    EXPECT_NE(runKiln(render + " -s 4 -a 5 0.1").err.find("adaptive sampling tests a pixel first"),
              std::string::npos);
    EXPECT_NE(runKiln(render + " -s 1 --denoise").err.find("--denoise needs 2 samples"),
              std::string::npos);
    EXPECT_EQ(runKiln(render + " -s 16 -a 4 0.1").err.find("adaptive sampling tests"),
              std::string::npos);
}

}  // namespace
}  // namespace kiln
