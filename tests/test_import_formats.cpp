// Formats other than COLLADA and PLY go through Assimp: node transforms composed, shared meshes
// instanced.
#include <filesystem>

#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(AssimpFormats, GltfMeshPlacedThreeTimesBecomesInstances) {
    auto dir = test::scratchDir();
    std::string gltf =
        R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}], "nodes": [{"mesh": 0, "translation": [0, 0, 0]}, {"mesh": 0, "translation": [5, 0, 0]}, {"mesh": 0, "translation": [0, 5, 0], "scale": [2, 2, 2]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
    Scene s = loadScene(test::writeFile(dir / "three.gltf", gltf));
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.uniqueTriangles, 1u);
    EXPECT_EQ(sum.triangles, 3u);
    EXPECT_EQ(sum.instances, 3u);
    Bounds3 b = s.storedBounds();
    EXPECT_NEAR(b.lo.x, 0, 1e-6);
    EXPECT_NEAR(b.hi.x, 6, 1e-6);  // the instance at x = 5
    EXPECT_NEAR(b.hi.y, 7, 1e-6);  // the scaled instance at y = 5 spans up to 5 + 2
}

TEST(AssimpFormats, AsciiStl) {
    auto dir = test::scratchDir();
    std::string stl =
        "solid t\n"
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
        "0\nendloop\nendfacet\n"
        "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 "
        "0\nendloop\nendfacet\n"
        "endsolid t\n";
    Scene s = loadScene(test::writeFile(dir / "quad.stl", stl));
    EXPECT_EQ(summarize(s).triangles, 2u);
}

// Issue #33 item 7: an empty part of a multi-part file is skipped with a warning naming it; the
// file was refused ("mesh emptySolid contains no vertices") though it holds a valid triangle. A
// file with nothing but empty parts stays an error.
TEST(AssimpFormats, EmptyPartsAreSkippedWithAWarning) {
    std::string corpus = "/usr/share/assimp/models/STL/triangle_with_empty_solid.stl";
    ASSERT_TRUE(std::filesystem::exists(corpus)) << "assimp-testmodels (tools/setup.sh) missing";
    Scene s = loadScene(corpus);
    EXPECT_EQ(summarize(s).triangles, 1u);
    EXPECT_TRUE(test::hasWarning(s, "mesh 'emptySolid' (part 2 of 2) has no vertices: skipped"));

    auto dir = test::scratchDir();
    const std::string triangle =
        "solid full\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
        "0\nendloop\nendfacet\nendsolid full\n";
    Scene between = loadScene(test::writeFile(
        dir / "three.stl", "solid a\nendsolid a\n" + triangle + "solid c\nendsolid c\n"));
    EXPECT_EQ(summarize(between).triangles, 1u);
    EXPECT_TRUE(test::hasWarning(between, "mesh 'a'"));
    EXPECT_TRUE(test::hasWarning(between, "mesh 'c'"));
    EXPECT_FALSE(test::hasWarning(between, "mesh 'full'"));
    test::expectError(
        test::writeFile(dir / "empty.stl", "solid a\nendsolid a\nsolid b\nendsolid b\n"), "");
}

TEST(AssimpFormats, ObjQuadsAreTriangulatedAndGroupsKept) {
    auto dir = test::scratchDir();
    std::string obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
        "o first\nf 1 2 3 4\no second\nf 5 6 7\n";
    Scene s = loadScene(test::writeFile(dir / "two.obj", obj));
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.triangles, 3u);
    EXPECT_EQ(sum.meshes, 2u);
}

}  // namespace
}  // namespace kiln
