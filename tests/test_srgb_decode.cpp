// sRGB-encoded colour is decoded through the OCIO config kiln follows: kiln's own config gives the
// IEC 61966-2-1 curve, a config whose sRGB space differs is followed, and one without an sRGB
// texture space falls back to the curve. Alpha and other channels are left alone.
#include <cmath>

#include "color/srgb_decode.h"
#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

double iecCurve(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

std::string writeConfig(const std::string& srgbSpace, const std::string& roles = "") {
    return test::writeFile(test::scratchDir() / "config.ocio", R"(ocio_profile_version: 2
roles:
  default: lin
  scene_linear: lin
)" + roles + R"(
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  sRGB:
    - !<View> {name: Raw, colorspace: lin}
colorspaces:
  - !<ColorSpace>
    name: lin
)" + srgbSpace);
}

// Above the toe, float rounding apart. In the toe OCIO's ExponentWithLinearTransform uses the
// slope that makes the curve continuous (12.9232) where the standard rounds it to 12.92: 2.5e-4
// relative.
TEST(SrgbDecode, KilnsConfigGivesTheIecCurve) {
    for (int code : {0, 5, 10, 11, 64, 128, 200, 255}) {
        double v = code / 255.0, want = iecCurve(v);
        double tolerance = v <= 0.04045 ? 3e-4 * want : 2e-7 + 1e-6 * want;
        EXPECT_NEAR(srgbToLinear(float(v)), want, tolerance) << code;
    }
}

TEST(SrgbDecode, ColourChannelsOnlyForAnyChannelCount) {
    float rgba[8] = {0.5f, 0.25f, 1.0f, 0.5f, 0.0f, 0.75f, 0.1f, 0.3f};
    decodeSrgbTexels(rgba, 2, 4);
    EXPECT_NEAR(rgba[0], iecCurve(0.5), 1e-6);
    EXPECT_NEAR(rgba[5], iecCurve(0.75), 1e-6);
    EXPECT_EQ(rgba[3], 0.5f);  // alpha
    EXPECT_EQ(rgba[7], 0.3f);
    float greyAlpha[4] = {0.5f, 0.5f, 0.25f, 0.25f};
    decodeSrgbTexels(greyAlpha, 2, 2);
    EXPECT_NEAR(greyAlpha[0], iecCurve(0.5), 1e-6);
    EXPECT_NEAR(greyAlpha[2], iecCurve(0.25), 1e-6);
    EXPECT_EQ(greyAlpha[1], 0.5f);
    EXPECT_EQ(greyAlpha[3], 0.25f);
}

TEST(SrgbDecode, FollowsTheConfigsSrgbSpace) {
    std::string gamma22 = writeConfig(R"(  - !<ColorSpace>
    name: sRGB
    to_reference: !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1]}
)");
    {
        test::ScopedEnv ocio("OCIO", gamma22);
        EXPECT_NEAR(srgbToLinear(0.5f), std::pow(0.5, 2.2), 1e-6);  // 0.2176, not 0.2140
    }
    EXPECT_NEAR(srgbToLinear(0.5f), iecCurve(0.5), 1e-6) << "back to kiln's config";
    test::ScopedEnv none("OCIO", writeConfig(""));
    EXPECT_NEAR(srgbToLinear(0.5f), iecCurve(0.5), 1e-6) << "no sRGB space: the curve";
}

// A long session (the Python module, a batch's frames) that edits its config is followed: the
// decoder is made again from the config as read now, not kept by the config's path.
TEST(SrgbDecode, AnEditedConfigIsFollowed) {
    auto withGamma = [](const std::string& gamma) {
        return writeConfig(
            "  - !<ColorSpace>\n    name: sRGB\n    to_reference: "
            "!<ExponentTransform> {value: [" +
            gamma + ", " + gamma + ", " + gamma + ", 1]}\n");
    };
    const std::string path = withGamma("2.2");
    test::ScopedEnv ocio("OCIO", path);
    EXPECT_NEAR(srgbToLinear(0.5f), std::pow(0.5, 2.2), 1e-6);
    ASSERT_EQ(withGamma("2.45"), path);  // the same file, rewritten
    EXPECT_NEAR(srgbToLinear(0.5f), std::pow(0.5, 2.45), 1e-6);
}

// A config whose sRGB texture space has a name kiln does not know is found through its
// texture_paint role, but only when that space is sRGB-encoded: ACES 1.x configs point the role at
// ACEScc and Blender's at a linear space, which must not decode 8-bit colour.
TEST(SrgbDecode, FollowsTheTexturePaintRoleToAnSrgbEncodedSpace) {
    const std::string paintSpace = R"(  - !<ColorSpace>
    name: studio_paint
    encoding: sdr-video
    to_reference: !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1]}
)";
    {
        test::ScopedEnv ocio("OCIO", writeConfig(paintSpace, "  texture_paint: studio_paint"));
        EXPECT_NEAR(srgbToLinear(0.5f), std::pow(0.5, 2.2), 1e-6);
    }
    EXPECT_NEAR(srgbToLinear(0.5f), iecCurve(0.5), 1e-6) << "back to kiln's config";
    const std::string logSpace = R"(  - !<ColorSpace>
    name: paint_log
    encoding: log
    to_reference: !<ExponentTransform> {value: [2.2, 2.2, 2.2, 1]}
)";
    test::ScopedEnv ocio("OCIO", writeConfig(logSpace, "  texture_paint: paint_log"));
    EXPECT_NEAR(srgbToLinear(0.5f), iecCurve(0.5), 1e-6) << "a log texture_paint is not sRGB";
}

}  // namespace
}  // namespace kiln
