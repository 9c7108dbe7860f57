// Vertex colours multiply the base colour: PLY red/green/blue (integer codes decoded from sRGB,
// floats linear), OBJ "v x y z r g b" (direct reader and Assimp), glTF COLOR_0 through Assimp.
#include <algorithm>

#include "integrators/path.h"
#include "renderer/accel/accelerator.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

Color vertexColour(const TriangleMesh& m, size_t v) {
    return Color(m.colors[3 * v], m.colors[3 * v + 1], m.colors[3 * v + 2]);
}

TEST(VertexColors, PlyUcharColoursAreDecodedFromSrgb) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(
        dir / "tri.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 0 128 0\n0 1 0 10 20 255\n3 0 1 2\n"));
    ASSERT_EQ(s.meshes.size(), 1u);
    const TriangleMesh& m = s.meshes[0];
    ASSERT_EQ(m.colors.size(), 9u);
    EXPECT_EQ(vertexColour(m, 0), Color(1, 0, 0));
    EXPECT_EQ(vertexColour(m, 1), Color(0, srgbToLinear(128 / 255.0f), 0));
    EXPECT_EQ(vertexColour(m, 2),
              Color(srgbToLinear(10 / 255.0f), srgbToLinear(20 / 255.0f), 1.0f));
}

TEST(VertexColors, PlyFloatColoursAreLinear) {
    Scene s = loadScene("/usr/share/assimp/models/PLY/float-color.ply");
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.meshes[0].colors.size(), 9u);
    for (size_t v = 0; v < 3; ++v) EXPECT_EQ(vertexColour(s.meshes[0], v), Color(0, 0, 1));
}

const std::string kColouredObj =
    "v 0 0 0 1 0 0\nv 1 0 0 0 0.5 0\nv 0 1 0 0 0 0.25\nv 1 1 0 0.2 0.4 0.6\n"
    "f 1 2 4\nf 1 4 3\n";

TEST(VertexColors, ObjDirectReaderKeepsColours) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(dir / "quad.obj", kColouredObj));
    ASSERT_EQ(s.meshes.size(), 1u);
    const TriangleMesh& m = s.meshes[0];
    ASSERT_EQ(m.colors.size(), 12u);
    EXPECT_EQ(vertexColour(m, 1), Color(0, 0.5f, 0));
    EXPECT_EQ(vertexColour(m, 3), Color(0.2f, 0.4f, 0.6f));
}

// With a material the OBJ goes to Assimp: its colour set 0 lands in the same place.
TEST(VertexColors, AssimpColourSetMatchesTheDirectReader) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.mtl", "newmtl m\nKd 1 1 1\n");
    Scene direct = loadScene(test::writeFile(dir / "direct.obj", kColouredObj));
    Scene assimp = loadScene(
        test::writeFile(dir / "assimp.obj", "mtllib quad.mtl\nusemtl m\n" + kColouredObj));
    ASSERT_EQ(assimp.meshes.size(), 1u);
    const TriangleMesh &a = assimp.meshes[0], &d = direct.meshes[0];
    ASSERT_EQ(a.colors.size(), 3 * a.vertexCount());
    // Assimp may reorder vertices, and keeps a coloured mesh's corners unshared: match them by
    // position; every vertex of the direct reader is found.
    std::vector<bool> matched(d.vertexCount(), false);
    for (size_t i = 0; i < a.vertexCount(); ++i)
        for (size_t j = 0; j < d.vertexCount(); ++j) {
            if (!(a.vertex(uint32_t(i)) == d.vertex(uint32_t(j)))) continue;
            EXPECT_EQ(vertexColour(a, i), vertexColour(d, j)) << "vertex " << i;
            matched[j] = true;
        }
    EXPECT_EQ(std::count(matched.begin(), matched.end(), true), ptrdiff_t(d.vertexCount()));
}

// A quad red at every vertex renders red: the albedo AOV is the material's albedo times (1, 0, 0).
TEST(VertexColors, ColoursMultiplyTheAlbedoInTheRender) {
    auto dir = test::scratchDir();
    Scene s =
        loadScene(test::writeFile(dir / "red.obj",
                                  "v 0 0 0 1 0 0\nv 1 0 0 1 0 0\nv 1 1 0 1 0 0\nv 0 1 0 1 0 0\n"
                                  "f 1 2 3\nf 1 3 4\n"));
    AovRequest aovs;
    aovs.add(AovKind::Albedo);
    auto accel = makeEmbreeAccelerator(s);
    Film f = test::renderJob(s, *accel, test::jobOptions(16, 16, 1, PathOptions{}, aovs));
    size_t r = test::aovChannel(f, "albedo.R"), g = test::aovChannel(f, "albedo.G");
    float plain = s.materials[s.meshes[0].materialOf(0)].albedo.x;
    int onQuad = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            if (f.aov(x, y, r) == 0) continue;  // background
            EXPECT_FLOAT_EQ(f.aov(x, y, r), plain);
            EXPECT_EQ(f.aov(x, y, g), 0.0f);
            ++onQuad;
        }
    EXPECT_GT(onQuad, 16);
}

}  // namespace
}  // namespace kiln
