// Help that helps: "did you mean" for a mistyped command, subcommand or option; kiln help COMMAND;
// bash completion of every command, subcommand, option and enumerated value (the script run by
// bash as completion runs it); the man page with every command's options and the environment.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>

#include "aces_config.h"
#include "kiln_run.h"
#include "renderer/cli/did_you_mean.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(Help, DidYouMeanForCommandsSubcommandsAndOptions) {
    EXPECT_EQ(editDistance("rendr", "render"), 1u);
    EXPECT_EQ(editDistance("", "abc"), 3u);
    EXPECT_EQ(nearestName("stauts", {"submit", "status", "merge"}), "status");
    EXPECT_EQ(nearestName("xyz", {"render", "info"}), "");
    test::CliRun command = test::runKiln("rendr scene.dae");
    EXPECT_EQ(command.code, 2);
    EXPECT_NE(command.err.find("unknown command 'rendr' (did you mean 'render'?)"),
              std::string::npos)
        << command.err;
    test::CliRun option = test::runKiln("render scene.dae --sp 4");
    EXPECT_EQ(option.code, 2);
    EXPECT_NE(option.err.find("(did you mean '--spp'?)"), std::string::npos) << option.err;
    test::CliRun farm = test::runKiln("farm stauts job.farm");
    EXPECT_EQ(farm.code, 2);
    EXPECT_NE(farm.err.find("(did you mean 'status'?)"), std::string::npos) << farm.err;
}

TEST(Help, HelpCommandIsTheCommandsHelp) {
    for (std::string command : {"render", "batch", "farm status", "bench accel"}) {
        test::CliRun help = test::runKiln("help " + command);
        test::CliRun direct = test::runKiln(command + " --help");
        EXPECT_EQ(help.code, 0) << command << help.err;
        EXPECT_EQ(help.out, direct.out) << command;
        EXPECT_NE(help.out.find("usage: kiln " + command), std::string::npos) << help.out;
    }
    EXPECT_NE(test::runKiln("help").out.find("help COMMAND"), std::string::npos);
}

// COMPREPLY for a command line whose last word is being completed.
std::string complete(const std::string& words) {
    std::string script = "source " + test::repo("tools/kiln-completion.bash") + "; COMP_WORDS=(" +
                         words + "); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); " +
                         "_kiln; echo \"${COMPREPLY[*]}\"";
    test::CliRun r = test::runProgram("bash", "-c " + test::shellQuoted(script));
    EXPECT_EQ(r.code, 0) << r.err;
    return " " + r.out.substr(0, r.out.find('\n')) + " ";
}

TEST(Help, CompletionKnowsEveryCommandSubcommandAndValue) {
    const std::string kiln = KILN_BINARY;
    std::string commands = complete(kiln + " ''");
    for (const char* c : {"render", "merge", "info", "crosscheck", "bench", "batch", "farm",
                          "tools", "report", "denoise", "help"})
        EXPECT_NE(commands.find(std::string(" ") + c + " "), std::string::npos) << c << commands;
    EXPECT_EQ(complete(kiln + " farm ''"), " submit status merge resubmit ");
    EXPECT_EQ(complete(kiln + " bench ''"), " accel plan accuracy ");
    EXPECT_EQ(complete(kiln + " render s.dae --progress ''"), " bar json none ");
    std::string aovs = complete(kiln + " render s.dae --aov ''");
    for (const char* a : {"emission", "crypto_object", "variance", "all", "default"})
        EXPECT_NE(aovs.find(std::string(" ") + a + " "), std::string::npos) << a << aovs;
    for (const char* command : {" render s.dae", " denoise in.exr"}) {
        std::string light = complete(kiln + command + " --denoise-aovs ''");
        for (const char* a : {"emission", "direct", "indirect_transmission", "bounces"})
            EXPECT_NE(light.find(std::string(" ") + a + " "), std::string::npos) << a << light;
        EXPECT_EQ(light.find(" albedo "), std::string::npos) << light;
    }
    EXPECT_NE(complete(kiln + " batch job.json --").find(" --dry-run "), std::string::npos);
    EXPECT_NE(complete(kiln + " farm status --").find(" --json "), std::string::npos);
    EXPECT_NE(complete(kiln + " farm submit s.dae --").find(" --sbatch-arg "), std::string::npos);
    EXPECT_NE(complete(kiln + " farm submit s.dae --").find(" --spp "), std::string::npos);
    EXPECT_EQ(complete(kiln + " farm submit s.dae --by ''"), " samples region frames ");
}

// --display, --view and --look complete to the names of the config kiln follows ($OCIO here),
// each name one word even when it holds spaces; a view of the --display given earlier.
TEST(Help, CompletionOffersTheConfigsDisplaysViewsAndLooks) {
    const std::string kiln = KILN_BINARY;
    std::string config = test::kAcesConfig;
    config.replace(config.find("Standard"), 8, "ACES 1.0 - SDR Video");
    auto dir = test::scratchDir();
    test::ScopedEnv ocio("OCIO", test::writeFile(dir / "aces.ocio", config));
    test::CliRun listed = test::runKiln("info --ocio");
    ASSERT_EQ(listed.code, 0) << listed.err;
    EXPECT_NE(listed.out.find("view\tsRGB\tACES 1.0 - SDR Video\n"), std::string::npos)
        << listed.out;
    EXPECT_NE(listed.out.find("scene_linear\tacescg\n"), std::string::npos) << listed.out;
    EXPECT_EQ(complete(kiln + " render s.dae --display ''"), " sRGB ");
    EXPECT_EQ(complete(kiln + " render s.dae --look B"), " Brighter ");
    std::string script = "source " + test::repo("tools/kiln-completion.bash") + "; COMP_WORDS=(" +
                         kiln + " render s.dae --display sRGB --view ''); COMP_CWORD=6; _kiln; " +
                         "printf '%s|' \"${COMPREPLY[@]}\"";
    test::CliRun r = test::runProgram("bash", "-c " + test::shellQuoted(script));
    EXPECT_EQ(r.out, "ACES 1.0 - SDR Video|");
    EXPECT_EQ(test::runKiln("info --ocio s.dae").code, 2);
    test::ScopedEnv bad("OCIO", test::writeFile(dir / "bad.ocio", "garbage: ["));
    test::CliRun refused = test::runKiln("info --ocio");
    EXPECT_EQ(refused.code, 2);
    EXPECT_NE(refused.err.find("bad.ocio"), std::string::npos) << refused.err;
}

TEST(Help, ManPageHasEveryCommandsOptionsExitStatusEnvironmentAndFiles) {
    std::string page = std::string(KILN_BUILD_DIR) + "/kiln.1";
    if (!std::filesystem::exists(page)) GTEST_SKIP() << "no help2man at build time";
    std::ifstream in(page);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    for (const char* part :
         {".SS kiln render", ".SS kiln batch", ".SS kiln farm submit", ".SS kiln farm status",
          "--dry-run", "--sbatch-arg", "--time-limit", "EXIT STATUS", "ENVIRONMENT",
          "KILN_TEXTURE_CACHE", "SLURM_ARRAY_TASK_ID", ".B OCIO", "FILES", "config.ocio"})
        EXPECT_NE(text.find(part), std::string::npos) << part;
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// A copy of the binary outside the build tree, with no share/kiln beside it, says where it looked
// and which config it uses; given share/kiln/config.ocio beside it, it takes that one silently.
TEST(Help, AMovedBinarySaysWhereItLookedForItsConfig) {
    namespace fs = std::filesystem;
    auto dir = test::scratchDir();
    fs::create_directories(dir / "bin");
    fs::copy_file(KILN_BINARY, dir / "bin/kiln", fs::copy_options::overwrite_existing);
    // Its image module goes with it (a moved binary needs it beside it, image_module.h).
    fs::copy_file(fs::path(KILN_BINARY).parent_path() / "kiln_image.so", dir / "bin/kiln_image.so",
                  fs::copy_options::overwrite_existing);
    test::ScopedEnv noOcio("OCIO", nullptr);
    std::string render = (dir / "bin/kiln").string() + " render " +
                         test::repo("scenes/cornell.dae") + " -r 8 6 -s 1 -q -o " +
                         (dir / "x").string();
    test::CliRun moved = test::runProgram(render, "");
    EXPECT_EQ(moved.code, 0) << moved.err;
    EXPECT_NE(moved.err.find("no " + (dir / "share/kiln/config.ocio").string() + " beside"),
              std::string::npos)
        << moved.err;
    EXPECT_NE(moved.err.find("using the source tree's"), std::string::npos) << moved.err;
    fs::create_directories(dir / "share/kiln");
    fs::copy_file(test::repo("color/config.ocio"), dir / "share/kiln/config.ocio",
                  fs::copy_options::overwrite_existing);
    test::CliRun installed = test::runProgram(render + " --json", "");
    EXPECT_EQ(installed.code, 0) << installed.err;
    EXPECT_EQ(installed.err.find("source tree"), std::string::npos) << installed.err;
    EXPECT_NE(installed.out.find((dir / "share/kiln/config.ocio").string()), std::string::npos);
}

// A render that reads no image but an EXR environment map writes its EXR and PNG without the image
// module (OpenImageIO and its ~250 libraries never load: a 16x16 render took 0.12 s, 0.49 s before;
// docs/performance.md); a heat map, a JPEG preview or a PNG map needs the module, and its absence
// is an error before any work.
TEST(Help, AnUntexturedRenderWritesItsImagesWithoutTheImageModule) {
    namespace fs = std::filesystem;
    auto dir = test::scratchDir();
    fs::copy_file(KILN_BINARY, dir / "kiln", fs::copy_options::overwrite_existing);
    const std::string render =
        (dir / "kiln").string() + " render " + test::repo("scenes/cornell.dae") + " -r 8 6 -s 1 -q";
    test::CliRun plain = test::runProgram(render + " -o " + (dir / "plain").string(), "");
    EXPECT_EQ(plain.code, 0) << plain.err;
    for (const char* file : {"plain.exr", "plain.png"}) {
        auto in = OIIO::ImageInput::open((dir / file).string());
        ASSERT_TRUE(in) << file;
        EXPECT_EQ(in->spec().width, 8);
    }
    for (const std::string& needsModule :
         {" -o " + (dir / "shown.jpg").string(), " -o " + (dir / "heat").string() + " --heatmap"}) {
        test::CliRun r = test::runProgram(render + needsModule, "");
        EXPECT_NE(r.code, 0) << needsModule;
        EXPECT_NE(r.err.find("cannot load kiln_image.so"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "shown.exr"));
    EXPECT_FALSE(fs::exists(dir / "heat.exr"));
    // An EXR environment map is read with OpenEXR alone (readExrRgb); a PNG one needs the module.
    test::CliRun lit = test::runProgram(render + " --env " + test::shared("envmaps/courtyard.exr") +
                                            " -o " + (dir / "lit").string(),
                                        "");
    EXPECT_EQ(lit.code, 0) << lit.err;
    EXPECT_TRUE(fs::exists(dir / "lit.exr"));
    ASSERT_TRUE(
        OIIO::ImageBuf(test::shared("envmaps/courtyard.exr")).write((dir / "map.png").string()));
    test::CliRun png = test::runProgram(
        render + " --env " + (dir / "map.png").string() + " -o " + (dir / "png").string(), "");
    EXPECT_NE(png.code, 0);
    EXPECT_NE(png.err.find("cannot load kiln_image.so"), std::string::npos) << png.err;
}

}  // namespace
}  // namespace kiln
