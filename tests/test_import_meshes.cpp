// The shared real meshes import with their listed counts, a default camera and light rig.
#include <algorithm>

#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

struct MeshExpected {
    const char* file;
    uint64_t vertices, triangles;
};

void PrintTo(const MeshExpected& e, std::ostream* os) { *os << e.file; }

class MeshImport : public ::testing::TestWithParam<MeshExpected> {};

TEST_P(MeshImport, CountsCameraAndLights) {
    const MeshExpected& e = GetParam();
    Scene s = loadScene(test::shared(std::string("meshes/") + e.file));
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.triangles, e.triangles);
    if (e.vertices) {
        EXPECT_EQ(sum.vertices, e.vertices);
    }
    EXPECT_FALSE(s.hasFileCamera);
    // Default rig: a key light and a sky fill; default framing looks at the bounds' centre.
    EXPECT_EQ(sum.lights, (std::map<std::string, int>{{"ambient", 1}, {"directional", 1}}));
    Bounds3 b = s.storedBounds();
    Vec3 toCentre = normalize(b.centroid() - s.camera.position);
    EXPECT_GT(dot(toCentre, s.camera.forward), 0.9999f);
    EXPECT_GT(length(b.centroid() - s.camera.position), 0.5f * length(b.diagonal()));
}

INSTANTIATE_TEST_SUITE_P(
    Shared, MeshImport,
    ::testing::Values(MeshExpected{"igea.ply", 134345, 268686},
                      MeshExpected{"igea_triangles.ply", 134345, 268686},
                      MeshExpected{"igea_subdiv1_1M.ply", 537374, 1074744},
                      // OBJ vertex counts change with Assimp's vertex joining; check faces.
                      MeshExpected{"ogre.obj", 0, 124008}, MeshExpected{"lucy.obj", 0, 99970},
                      MeshExpected{"nefertiti.obj", 0, 99938},
                      MeshExpected{"stanford-bunny.obj", 0, 69451}),
    [](const auto& info) {
        std::string n = info.param.file;
        for (char& c : n)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return n;
    });

// Triangles as index triples rotated so the smallest index comes first (winding kept).
std::vector<std::array<uint32_t, 3>> canonicalTriangles(const TriangleMesh& m) {
    std::vector<std::array<uint32_t, 3>> tris;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        std::array<uint32_t, 3> a{m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]};
        std::rotate(a.begin(), std::min_element(a.begin(), a.end()), a.end());
        tris.push_back(a);
    }
    std::sort(tris.begin(), tris.end());
    return tris;
}

TEST(PlyTristrips, DecodeToTheSameTrianglesAsTheRewrittenFile) {
    // igea.ply stores one tristrips element (Assimp reads it as one triangle); igea_triangles.ply
    // is the same mesh rewritten as a face list. Same vertices, so the same triangles with the same
    // winding.
    Scene strips = loadScene(test::shared("meshes/igea.ply"));
    Scene faces = loadScene(test::shared("meshes/igea_triangles.ply"));
    ASSERT_EQ(strips.meshes.size(), 1u);
    ASSERT_EQ(faces.meshes.size(), 1u);
    EXPECT_EQ(canonicalTriangles(strips.meshes[0]), canonicalTriangles(faces.meshes[0]));
    EXPECT_EQ(strips.meshes[0].positions, faces.meshes[0].positions);
}

TEST(EnvironmentOption, AddsAnEnvironmentLightInsteadOfTheRig) {
    LoadOptions o;
    o.environmentMap = test::shared("envmaps/studio.exr");
    Scene s = loadScene(test::shared("meshes/stanford-bunny.obj"), o);
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.lights, (std::map<std::string, int>{{"environment", 1}}));
}

TEST(OwnScenes, CornellBoxUsesItsFileCamera) {
    Scene s = loadScene(test::repo("scenes/cornell.dae"));
    EXPECT_TRUE(s.hasFileCamera);
    EXPECT_FALSE(s.framedByCourseRule);  // Y-up COLLADA of ours: the camera as written
    EXPECT_NEAR(s.camera.position.z, 4.6f, 1e-6f);
    EXPECT_EQ(s.spheres.size(), 2u);
    EXPECT_EQ(summarize(s).lights, (std::map<std::string, int>{{"area", 1}}));
}

}  // namespace
}  // namespace kiln
