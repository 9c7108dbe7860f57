// cmake --install into a temporary prefix: the binary renders from there with the config installed
// beside it (not the source tree's), with an ACES-style $OCIO too, and the man page and bash
// completion are in place.
#include <nlohmann/json.hpp>

#include "aces_config.h"
#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(Install, InstalledKilnRendersWithItsOwnConfig) {
    auto prefix = test::scratchDir() / "prefix with space";
    test::CliRun install =
        test::runProgram("cmake", "--install " + test::shellQuoted(KILN_BUILD_DIR) + " --prefix " +
                                      test::shellQuoted(prefix.string()) + " >/dev/null");
    ASSERT_EQ(install.code, 0) << install.err;
    auto bin = prefix / "bin" / "kiln", config = prefix / "share" / "kiln" / "config.ocio";
    ASSERT_TRUE(std::filesystem::exists(bin));
    ASSERT_TRUE(std::filesystem::exists(config));
    EXPECT_TRUE(std::filesystem::exists(prefix / "share/bash-completion/completions/kiln"));
    if (test::runProgram("which", "help2man >/dev/null").code == 0) {
        EXPECT_TRUE(std::filesystem::exists(prefix / "share/man/man1/kiln.1"));
    }

    // Without $OCIO, from another directory: the installed config, found from the binary.
    auto out = prefix / "render";
    test::CliRun r =
        test::runProgram("cd / && env -u OCIO " + test::shellQuoted(bin.string()),
                         "render " + test::repo("scenes/cornell.dae") +
                             " -r 24 18 -s 2 -q --json -o " + test::shellQuoted(out.string()));
    ASSERT_EQ(r.code, 0) << r.err;
    auto result = nlohmann::json::parse(r.out);
    EXPECT_EQ(result["ocio_config"], config.string());
    EXPECT_TRUE(std::filesystem::exists(out.string() + ".exr"));
    EXPECT_TRUE(std::filesystem::exists(out.string() + ".png"));
    // With an ACES-style $OCIO (scene_linear = ACEScg): the installed binary renders in it.
    std::string aces = test::writeFile(prefix / "aces.ocio", test::kAcesConfig);
    auto acesOut = prefix / "render-aces";
    test::CliRun a = test::runProgram(
        "cd / && OCIO=" + test::shellQuoted(aces) + " " + test::shellQuoted(bin.string()),
        "render " + test::repo("scenes/cornell.dae") + " -r 24 18 -s 2 -q --json -o " +
            test::shellQuoted(acesOut.string()));
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_EQ(nlohmann::json::parse(a.out)["ocio_config"], aces);
    EXPECT_TRUE(std::filesystem::exists(acesOut.string() + ".exr"));
    test::CliRun version = test::runProgram(test::shellQuoted(bin.string()), "--version");
    EXPECT_EQ(version.code, 0);
    EXPECT_NE(version.out.find("commit"), std::string::npos) << version.out;
    EXPECT_NE(version.out.find("OpenImageIO"), std::string::npos) << version.out;
}

}  // namespace
}  // namespace kiln
