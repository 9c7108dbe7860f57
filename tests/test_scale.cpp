// Scale tooling: midpoint subdivision, binary PLY round trip, .kiln scenes that place meshes by
// path and instance them, instanced against flattened renders, and the memory estimate that refuses
// early.
#include <cstdlib>
#include <map>

#include "integrators/path.h"
#include "renderer/render_loop.h"
#include "scene/importers.h"
#include "scene/mesh_tools.h"
#include "scene/scene_error.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

size_t boundaryEdges(const TriangleMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t < m.triangleCount(); ++t)
        for (int e = 0; e < 3; ++e) {
            uint32_t a = m.indices[3 * t + size_t(e)], b = m.indices[3 * t + size_t(e + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    size_t n = 0;
    for (const auto& [edge, count] : edges) n += count != 2;
    return n;
}

TEST(Subdivision, CountsBoundsAndClosedness) {
    TriangleMesh ball = test::sphereMesh(8, 16);
    // Weld the duplicated pole vertices so the mesh is closed by index.
    TriangleMesh sub = subdivideMidpoint(ball);
    EXPECT_EQ(sub.triangleCount(), 4 * ball.triangleCount());
    Bounds3 a, b;
    for (size_t v = 0; v < ball.vertexCount(); ++v) a.extend(ball.vertex(uint32_t(v)));
    for (size_t v = 0; v < sub.vertexCount(); ++v) b.extend(sub.vertex(uint32_t(v)));
    EXPECT_EQ(a.lo, b.lo);
    EXPECT_EQ(a.hi, b.hi);
    EXPECT_EQ(boundaryEdges(sub),
              2 * boundaryEdges(ball));  // each boundary edge splits in two; none appear
    // The shared igea_subdiv1_1M.ply was made by one level of this subdivision of igea.ply.
    Scene igea = loadScene(test::shared("meshes/igea.ply"));
    TriangleMesh one = subdivideMidpoint(igea.meshes[0]);
    EXPECT_EQ(one.vertexCount(), 537374u);
    EXPECT_EQ(one.triangleCount(), 1074744u);
}

TEST(Subdivision, BinaryPlyRoundTrip) {
    TriangleMesh grid = test::gridMesh(5, 4, 0.3f);
    std::string path = (test::scratchDir() / "grid.ply").string();
    writeBinaryPly(path, grid);
    Scene back = loadScene(path);
    ASSERT_EQ(back.meshes.size(), 1u);
    EXPECT_EQ(back.meshes[0].indices, grid.indices);
    for (size_t v = 0; v < grid.vertexCount();
         ++v)  // recentred on load: compare with the origin added
        EXPECT_EQ(Vec3(Vec3d(back.meshes[0].vertex(uint32_t(v))) + back.origin),
                  grid.vertex(uint32_t(v)));
}

// A binary PLY of a w x h grid whose faces are triangle records, except face `quadAt` (a quad made
// of the next two triangles, when below the count) and an out-of-range index at face `badAt`.
std::string gridPly(const std::filesystem::path& path, const TriangleMesh& grid, size_t quadAt,
                    size_t badAt) {
    size_t faces = grid.triangleCount() - (quadAt < grid.triangleCount() ? 1 : 0);
    std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                      std::to_string(grid.vertexCount()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(faces) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    out.append(reinterpret_cast<const char*>(grid.positions.data()), 12 * grid.vertexCount());
    for (size_t t = 0, f = 0; t < grid.triangleCount(); ++t, ++f) {
        const uint32_t* idx = &grid.indices[3 * t];
        if (f == quadAt) {  // gridMesh's triangle pairs are (a b c) (a c d): one quad a b c d
            uint32_t quad[4] = {idx[0], idx[1], idx[2], grid.indices[3 * t + 5]};
            out.push_back(4);
            out.append(reinterpret_cast<const char*>(quad), 16);
            ++t;
            continue;
        }
        uint32_t tri[3] = {idx[0], idx[1], f == badAt ? uint32_t(grid.vertexCount()) : idx[2]};
        out.push_back(3);
        out.append(reinterpret_cast<const char*>(tri), 12);
    }
    return test::writeFile(path, out);
}

TEST(PlyFastPath, HandsOverToTheGeneralReaderAtAQuadAndNamesBadFaces) {
    // 320 x 320 cells: 204,800 triangle records.
    TriangleMesh grid = test::gridMesh(320, 320, 0.01f);
    auto dir = test::scratchDir();
    Scene all = loadScene(gridPly(dir / "all.ply", grid, SIZE_MAX, SIZE_MAX));
    EXPECT_EQ(all.meshes[0].indices, grid.indices);
    // A quad at face 150,000: the fast path stops there, the general reader fan-triangulates it
    // into the same two triangles and reads on.
    Scene mixed = loadScene(gridPly(dir / "mixed.ply", grid, 150000, SIZE_MAX));
    EXPECT_EQ(mixed.meshes[0].indices, grid.indices);
    test::expectError(gridPly(dir / "bad.ply", grid, SIZE_MAX, 123457),
                      "face 123457 has vertex index 103041 out of range");
}

TEST(KilnScene, CornellLucyPlacesTheMeshByPathInsideTheBox) {
    Scene s = loadScene(test::repo("scenes/cornell_lucy.kiln"));
    SceneSummary sum = summarize(s);
    EXPECT_EQ(sum.triangles, 99970u + 12u);  // lucy.obj + CBempty's box
    EXPECT_EQ(sum.materials.at("glass"), 1);
    Bounds3 b = worldBoundsOf(s);
    EXPECT_NEAR(b.lo.y, 0.0f, 1e-5f);  // Lucy stands on the floor, inside the 2 x 1.5 x 2 box
    EXPECT_LE(b.hi.y, 1.50001f);
    EXPECT_TRUE(s.hasFileCamera);
}

std::string instanceScene(const std::filesystem::path& dir, bool flattened) {
    std::string mesh = test::shared("meshes/stanford-bunny.obj");
    std::string xml = "<kiln-scene>\n<material name=\"white\" albedo=\"0.7 0.7 0.7\"/>\n";
    if (flattened) {
        for (int z = 0; z < 2; ++z)
            for (int x = 0; x < 3; ++x)
                xml += "<mesh file=\"" + mesh + "\" material=\"white\"><fit center=\"" +
                       std::to_string(x * 1.5) + " 0 " + std::to_string(z * 1.5) +
                       "\" size=\"1\"/></mesh>\n";
    } else {
        xml += "<instances file=\"" + mesh +
               "\" material=\"white\" grid=\"3 1 2\" spacing=\"1.5\"><fit center=\"0 0 0\" "
               "size=\"1\"/></instances>\n";
    }
    xml +=
        "<light kind=\"directional\" direction=\"0.3 -1 -0.4\" radiance=\"2 2 2\"/>\n<light "
        "kind=\"ambient\" "
        "radiance=\"0.3 0.3 0.3\"/>\n<camera position=\"1.5 2.5 5\" look-at=\"1.5 0.4 0.75\" "
        "fov=\"45\"/>\n</kiln-scene>\n";
    return test::writeFile(dir / (flattened ? "flat.kiln" : "instanced.kiln"), xml);
}

TEST(KilnScene, InstancedAndFlattenedRenderTheSameImage) {
    auto dir = test::scratchDir();
    Scene inst = loadScene(instanceScene(dir, false)), flat = loadScene(instanceScene(dir, true));
    EXPECT_EQ(summarize(inst).instances, 6u);
    EXPECT_EQ(summarize(inst).uniqueTriangles, 69451u);
    EXPECT_EQ(summarize(inst).triangles, 6u * 69451u);
    EXPECT_EQ(summarize(flat).triangles, 6u * 69451u);
    auto render = [](const Scene& s) {
        auto accel = makeEmbreeAccelerator(s);
        return test::renderJob(s, *accel, test::jobOptions(32, 24, 32));
    };
    Film a = render(inst), b = render(flat);
    int blocks = 0, mismatched = 0;
    for (int by = 0; by < 24; by += 8)
        for (int bx = 0; bx < 32; bx += 8) {
            double ma = 0, mb = 0, va = 0, vb = 0;
            for (int y = by; y < by + 8; ++y)
                for (int x = bx; x < bx + 8; ++x) {
                    ma += luminance(a.pixel(x, y)) / 64, mb += luminance(b.pixel(x, y)) / 64;
                    va += a.luminanceVariance(x, y) / (64.0 * 64.0),
                        vb += b.luminanceVariance(x, y) / (64.0 * 64.0);
                }
            ++blocks;
            mismatched += std::abs(ma - mb) > 5 * std::sqrt(va + vb) + 1e-6;
        }
    EXPECT_EQ(mismatched, 0) << "of " << blocks << " blocks";
}

TEST(KilnScene, BadInputIsOneLine) {
    auto dir = test::scratchDir();
    for (auto [text, what] :
         {std::pair{"<kiln-scene><teapot/></kiln-scene>", "unknown element <teapot>"},
          std::pair{"<kiln-scene><mesh/></kiln-scene>", "needs a file attribute"},
          std::pair{"<kiln-scene><mesh file=\"nope.obj\"/></kiln-scene>", "no such file"},
          std::pair{
              "<kiln-scene><camera position=\"0 0\" look-at=\"0 0 -1\" fov=\"40\"/></kiln-scene>",
              "needs 3 numbers"},
          std::pair{"<scene/>", "not a kiln scene"}}) {
        std::string path = test::writeFile(dir / "bad.kiln", text);
        try {
            loadScene(path);
            ADD_FAILURE() << text;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
}

TEST(MemoryEstimate, RefusesBeforeAllocating) {
    {
        test::ScopedMemoryLimit limit("1000000");  // 1 MB
        try {
            loadScene(test::shared("meshes/igea_subdiv1_1M.ply"));
            ADD_FAILURE() << "no error";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find("would need about"), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find("1074744 faces"), std::string::npos) << e.what();
        }
    }
    EXPECT_NO_THROW(checkMemoryFor("x", 1000, 2000));
}

}  // namespace
}  // namespace kiln
