// Cryptomatte names objects by the scene node that places them, as Cycles and Arnold do:
// CBspheres.dae's node "Sphere2" instances the geometry "Sphere1-data", and each sphere gets its
// own matte; instanced meshes take their node's name; materials keep their own names.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "integrators/crypto_names.h"
#include "kiln_run.h"
#include "renderer/film/cryptomatte.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(CryptoNames, SpheresAreNamedByTheirNodesAndEachHasItsOwnMatte) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    CryptoNames names(s);
    EXPECT_EQ(names.spheres, (std::vector<std::string>{"Sphere1", "Sphere2"}));
    // Through the written file: both in the manifest, and both ids seen in rank 0 of some pixels.
    std::string out = (test::scratchDir() / "spheres").string();
    test::CliRun r =
        test::runKiln("render " + test::cs184("sky/CBspheres.dae") +
                      " -r 32 24 -s 4 -q --aov crypto_object,crypto_material -o " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open(out + ".exr");
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    auto manifest = nlohmann::json::parse(
        spec.get_string_attribute("cryptomatte/" + cryptoLayerKey("CryptoObject") + "/manifest"));
    ASSERT_TRUE(manifest.contains("Sphere1") && manifest.contains("Sphere2")) << manifest.dump();
    EXPECT_NE(manifest["Sphere1"], manifest["Sphere2"]);
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    int rank0 = spec.channelindex("CryptoObject00.R");
    std::set<float> seen;
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        seen.insert(px[p * size_t(spec.nchannels) + size_t(rank0)]);
    for (const char* sphere : {"Sphere1", "Sphere2"}) {
        uint32_t bits = uint32_t(std::stoul(manifest[sphere].get<std::string>(), nullptr, 16));
        EXPECT_TRUE(seen.count(cryptoIdFloat(bits))) << sphere << " has no pixel";
    }
    // Materials by their own names.
    auto materials = nlohmann::json::parse(
        spec.get_string_attribute("cryptomatte/" + cryptoLayerKey("CryptoMaterial") + "/manifest"));
    for (const Material& m : s.materials) EXPECT_TRUE(materials.contains(m.name)) << m.name;
}

TEST(CryptoNames, InstancesTakeTheirNodesNameAndFallBackToTheMesh) {
    Scene s = test::sceneWith(test::gridMesh(1, 1));
    s.meshes[0].name = "leaf-geometry";
    s.instances.push_back(Instance::place(0, Mat4::identity(), "leaf_left"));
    s.instances.push_back(Instance::place(0, Mat4::identity(), "leaf_right"));
    s.instances.push_back(Instance::place(0, Mat4::identity()));
    CryptoNames names(s);
    EXPECT_EQ(names.instances,
              (std::vector<std::string>{"leaf_left", "leaf_right", "leaf-geometry#2"}));
    s.meshes[0].node = "tree";
    EXPECT_EQ(CryptoNames(s).meshes[0], "tree");
}

}  // namespace
}  // namespace kiln
