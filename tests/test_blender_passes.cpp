// Every pass of kiln's EXR reaches Blender's compositor. Blender's multilayer EXR reader
// (imbuf's openexr_api.cpp, imb_exr_split_channel_name) takes a channel "LAYER.TOKEN" only when
// TOKEN is one letter (or two ending in X, Y, Z, R, G, B, U, V or A, or "red", "green", "blue",
// "alpha"), and drops the channel otherwise ("multilayer read: unknown channel token");
// single-channel layers are therefore named LAYER.X, as Blender writes its own (IndexOB.X). Checked
// through OIIO with the stricter rule every compositor reads (one of R G B A X Y Z W U V), and,
// where Blender is installed, through Blender's own reader in background mode.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <set>

#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// Every AOV, one render.
std::string renderEveryAov(const fs::path& dir) {
    std::string out = (dir / "all").string();
    test::CliRun r = test::runKiln("render " + test::cs184("sky/CBspheres_lambertian.dae") +
                                   " -r 16 12 -s 2 -q --aov all -o " + out);
    EXPECT_EQ(r.code, 0) << r.err;
    return out + ".exr";
}

// The layers of the file (the part of each channel name before its last '.'), and the channels
// whose last token breaks the rule.
std::set<std::string> layersOf(const std::string& exr, std::vector<std::string>& unreadable) {
    auto in = OIIO::ImageInput::open(exr);
    EXPECT_TRUE(in) << exr;
    std::set<std::string> layers;
    if (!in) return layers;
    for (const std::string& name : in->spec().channelnames) {
        size_t dot = name.rfind('.');
        std::string token = dot == std::string::npos ? name : name.substr(dot + 1);
        if (token.size() != 1 || std::string("RGBAXYZWUV").find(token) == std::string::npos)
            unreadable.push_back(name);
        if (dot != std::string::npos) layers.insert(name.substr(0, dot));
    }
    return layers;
}

TEST(BlenderPasses, EveryChannelNameIsOneBlenderReads) {
    auto dir = test::scratchDir();
    std::vector<std::string> unreadable;
    std::set<std::string> layers = layersOf(renderEveryAov(dir), unreadable);
    EXPECT_TRUE(unreadable.empty()) << unreadable.front();
    for (const char* single : {"samples", "variance", "primid", "objectid"})
        EXPECT_TRUE(layers.count(single)) << single;
}

TEST(BlenderPasses, BlendersReaderShowsEveryLayerAsAPass) {
    if (!fs::exists("/usr/bin/blender")) GTEST_SKIP() << "no Blender at /usr/bin/blender";
    auto dir = test::scratchDir();
    std::string exr = renderEveryAov(dir);
    std::vector<std::string> unreadable;
    std::set<std::string> layers = layersOf(exr, unreadable);
    std::string script = test::writeFile(dir / "passes.py", R"(import bpy, sys
scene = bpy.context.scene
scene.use_nodes = True
node = scene.node_tree.nodes.new("CompositorNodeImage")
node.image = bpy.data.images.load(sys.argv[sys.argv.index("--") + 1])
for output in node.outputs:
    print("PASS", output.name)
)");
    test::CliRun r = test::runProgram(
        "/usr/bin/blender", "-b --factory-startup -noaudio --python " + script + " -- " + exr);
    ASSERT_EQ(r.code, 0) << r.err;
    std::string all = r.out + r.err;
    EXPECT_EQ(all.find("unknown channel token"), std::string::npos) << all;
    for (const std::string& layer : layers)
        EXPECT_NE(r.out.find("PASS " + layer + "\n"), std::string::npos) << layer << "\n" << r.out;
}

}  // namespace
}  // namespace kiln
