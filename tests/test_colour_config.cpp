// $OCIO followed fully and checked before any work: defaults from the config, scene_linear by role
// or alias, missing pieces refused with one line and exit 2 before the scene is read.
#include <OpenImageIO/imageio.h>

#include "color/color_config.h"
#include "color/ocio_configs.h"
#include "color/working_space.h"
#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

// A config with its own working-space name, display and views: kiln must take all of them from it.
std::string config(const std::string& roles, const std::string& extraView = "",
                   const std::string& linearSpace = "") {
    return R"(ocio_profile_version: 2
roles:
)" + roles +
           R"(
displays:
  Studio Monitor:
    - !<View> {name: Show Look, colorspace: display_srgb}
    - !<View> {name: Flat, colorspace: linear_srgb})" +
           extraView + R"(
active_displays: []
active_views: []
colorspaces:
  - !<ColorSpace>
    name: linear_srgb
    isdata: false
)" + linearSpace +
           R"(
  - !<ColorSpace>
    name: display_srgb
    isdata: false
    from_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055, direction: inverse}
  - !<ColorSpace>
    name: acescg
    isdata: false
    from_reference: !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
  - !<ColorSpace>
    name: aces
    isdata: false
    from_reference: !<GroupTransform>
      children:
        - !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
        - !<BuiltinTransform> {style: ACEScg_to_ACES2065-1}
)";
}

const std::string kGoodRoles =
    "  default: linear_srgb\n  scene_linear: linear_srgb\n  aces_interchange: aces\n";

std::string render(const std::string& scene, const std::filesystem::path& out,
                   const std::string& extra = "") {
    return "render " + scene + " -r 16 12 -s 1 -q -o " + out.string() + " " + extra;
}

TEST(ColourConfig, ShippedConfigHasTheRolesAndPassesEveryCheck) {
    ColorSetup setup = checkColorConfig();
    EXPECT_EQ(setup.sceneLinear, "lin_rec709");
    EXPECT_EQ(setup.display, "sRGB");
    EXPECT_EQ(setup.view, "Standard");
    EXPECT_TRUE(setup.warnings.empty());
    test::CliRun check =
        test::runProgram("ociocheck", "--iconfig " + test::repo("color/config.ocio"));
    EXPECT_EQ(check.code, 0) << check.out;
    EXPECT_EQ(check.out.find("WARNING"), std::string::npos) << check.out;
    EXPECT_EQ(check.out.find("ERROR"), std::string::npos) << check.out;
}

// A process reads its config once (each frame of a batch checked it and made the preview's
// transform from it: 3-4 reads), and again when the file or the environment it was read in changes:
// a Python session that edits the config, or sets a context variable or the active displays.
TEST(ColourConfig, AConfigIsReadOnceUntilItsFileOrEnvironmentChanges) {
    auto dir = test::scratchDir();
    std::string text = config(kGoodRoles);
    text.insert(text.find('\n') + 1, "environment: {KILN_TEST_SHOT: a}\n");
    const std::string path = test::writeFile(dir / "studio.ocio", text);
    auto shot = [&] {
        return std::string(
            sharedOcioConfig(path)->getCurrentContext()->resolveStringVar("$KILN_TEST_SHOT"));
    };
    const auto first = sharedOcioConfig(path);
    EXPECT_EQ(sharedOcioConfig(path), first);
    std::string stamp = ocioConfigStamp(path);
    EXPECT_EQ(ocioConfigStamp(path), stamp);
    EXPECT_EQ(shot(), "a");
    {
        test::ScopedEnv set("KILN_TEST_SHOT", "b");
        EXPECT_EQ(shot(), "b");
        EXPECT_NE(ocioConfigStamp(path), stamp);
        stamp = ocioConfigStamp(path);
    }
    EXPECT_EQ(shot(), "a");
    EXPECT_NE(ocioConfigStamp(path), stamp);
    stamp = ocioConfigStamp(path);
    {
        test::ScopedEnv active("OCIO_ACTIVE_DISPLAYS", "Studio Monitor");
        EXPECT_NE(ocioConfigStamp(path), stamp);
    }
    stamp = ocioConfigStamp(path);
    EXPECT_EQ(ocioConfigStamp(path), stamp);
    test::writeFile(dir / "studio.ocio", text + "\n");  // edited: one byte more
    EXPECT_NE(ocioConfigStamp(path), stamp);
}

// The working space follows an edited config: it is described once per read of the config, not
// once per path for the life of the process.
TEST(ColourConfig, AnEditedConfigsWorkingSpaceIsFollowed) {
    auto dir = test::scratchDir();
    const std::string path = test::writeFile(dir / "studio.ocio", config(kGoodRoles));
    test::ScopedEnv ocio("OCIO", path);
    EXPECT_TRUE(workingSpace().rec709);
    EXPECT_EQ(workingSpace().name, "linear_srgb");
    test::writeFile(path, config("  default: acescg\n  scene_linear: acescg\n"
                                 "  aces_interchange: aces\n"));
    EXPECT_EQ(workingSpace().name, "acescg");
    EXPECT_FALSE(workingSpace().rec709);
    EXPECT_EQ(checkColorConfig().sceneLinear, "acescg");
}

TEST(ColourConfig, DefaultsAndWorkingSpaceComeFromOcio) {
    auto dir = test::scratchDir();
    test::ScopedEnv ocio("OCIO", test::writeFile(dir / "studio.ocio", config(kGoodRoles)));
    ColorSetup setup = checkColorConfig();
    EXPECT_EQ(setup.sceneLinear, "linear_srgb");
    EXPECT_EQ(setup.display, "Studio Monitor");
    EXPECT_EQ(setup.view, "Show Look");
    test::CliRun r = test::runKiln(render(test::repo("scenes/cornell.dae"), dir / "out"));
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open((dir / "out.exr").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("kiln:display"), "Studio Monitor");
    EXPECT_EQ(in->spec().get_string_attribute("kiln:view"), "Show Look");
    EXPECT_EQ(in->spec().get_string_attribute("kiln:colorspace"), "linear_srgb");
    // By alias when there is no role.
    std::string aliased =
        config("  default: linear_srgb\n  aces_interchange: aces\n", "", "    aliases: [linear]\n");
    test::ScopedEnv alias("OCIO", test::writeFile(dir / "alias.ocio", aliased));
    EXPECT_EQ(checkColorConfig().sceneLinear, "linear_srgb");
}

// Each config lacks something kiln needs: refused in one line naming the config, exit 2, before
// the scene is read (the scene path does not even exist) and without any output.
TEST(ColourConfig, ConfigsLackingWhatKilnNeedsAreRefusedBeforeAnyWork) {
    auto dir = test::scratchDir();
    struct Case {
        const char* name;
        std::string text;
        const char* says;
    };
    const Case cases[] = {
        {"no-scene-linear", config("  default: display_srgb\n"), "scene_linear"},
        {"unknown-look", config(kGoodRoles), "unknown look 'Nope'"},
        {"missing-lut",
         config(kGoodRoles, "\n    - !<View> {name: Film, colorspace: film_lut}") +
             "  - !<ColorSpace>\n    name: film_lut\n    from_reference: !<FileTransform> "
             "{src: no_such_lut.cube}\n",
         "no_such_lut"},
        {"not-yaml", "ocio_profile_version: 2\nroles: [\n", "OCIO"},
    };
    for (const Case& c : cases) {
        std::string path = test::writeFile(dir / (std::string(c.name) + ".ocio"), c.text);
        test::ScopedEnv ocio("OCIO", path);
        std::string extra = std::string(c.name) == "missing-lut"    ? "--view Film"
                            : std::string(c.name) == "unknown-look" ? "--look Nope"
                                                                    : "";
        test::CliRun r = test::runKiln(render("/nonexistent/scene.dae", dir / c.name, extra));
        EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << ": " << r.err;
        EXPECT_NE(r.err.find(path), std::string::npos) << c.name << ": " << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << c.name << ": " << r.err;
        EXPECT_EQ(r.err.find("scene.dae"), std::string::npos) << c.name << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / (std::string(c.name) + ".exr")));
    }
}

// Blender's own config, where installed: kiln follows its defaults, and a view it lacks is refused
// before any work.
TEST(ColourConfig, BlendersConfig) {
    const std::string blender = "/usr/share/blender/datafiles/colormanagement/config.ocio";
    if (!std::filesystem::exists(blender)) GTEST_SKIP() << blender << " not installed";
    auto dir = test::scratchDir();
    test::ScopedEnv ocio("OCIO", blender);
    test::CliRun bad =
        test::runKiln(render("/nonexistent/scene.dae", dir / "bad", "--view 'No Such View'"));
    EXPECT_EQ(bad.code, 2) << bad.err;
    EXPECT_NE(bad.err.find(blender), std::string::npos) << bad.err;
    test::CliRun r = test::runKiln(render(test::repo("scenes/cornell.dae"), dir / "out"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out.png"));
}

}  // namespace
}  // namespace kiln
