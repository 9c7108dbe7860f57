// The direct OBJ reader: same geometry as Assimp, every corner form, chunk boundaries, the Assimp
// fallback for what it does not handle, and errors that name the file and line.
#include <algorithm>
#include <array>
#include <cstdlib>

#include "scene/importers.h"
#include "scene/mesh_tools.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// Triangle corners as positions, in order: independent of how vertices are numbered.
std::vector<float> cornerPositions(const Scene& s) {
    std::vector<float> out;
    for (const TriangleMesh& m : s.meshes)
        for (uint32_t i : m.indices)
            out.insert(out.end(),
                       {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]});
    return out;
}

TEST(ObjReader, SameTrianglesAndMaterialAsAssimp) {
    for (const char* name : {"meshes/lucy.obj", "meshes/stanford-bunny.obj", "meshes/ogre.obj"}) {
        std::string path = test::shared(name);
        Scene direct, viaAssimp;
        ASSERT_TRUE(readObj(path, direct)) << name;
        importWithAssimp(path, nullptr, viaAssimp);
        // Assimp's float parser is off by one ulp on about 1 % of the numbers; from_chars rounds
        // correctly (lucy's "-7.72489" is -7.72489023, not Assimp's -7.72488976).
        std::vector<float> a = cornerPositions(direct), b = cornerPositions(viaAssimp);
        ASSERT_EQ(a.size(), b.size()) << name;
        size_t beyondOneUlp = 0;
        for (size_t i = 0; i < a.size(); ++i)
            beyondOneUlp += a[i] != b[i] && std::nextafter(b[i], a[i]) != a[i];
        EXPECT_EQ(beyondOneUlp, 0u) << name;
        ASSERT_EQ(direct.materials.size(), 1u);
        EXPECT_EQ(direct.materials[0].name, viaAssimp.materials[0].name);
        EXPECT_EQ(direct.materials[0].albedo.x, viaAssimp.materials[0].albedo.x);
    }
}

TEST(ObjReader, EveryCornerFormNegativeIndicesPolygonsAndCrlf) {
    auto dir = test::scratchDir();
    // A quad and a pentagon (fan-triangulated), relative indices, groups, comments, CRLF, blank
    // lines, tabs.
    std::string path = test::writeFile(dir / "forms.obj",
                                       "# comment\r\n"
                                       "o thing\r\n"
                                       "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                                       "\r\n"
                                       "g first\r\n"
                                       "f 1 2 3 4\r\n"
                                       "v 2 0 0\r\n"
                                       "s off\r\n"
                                       "f\t-1 -4   -3 -2 1 # a pentagon\r\n"
                                       "# no newline at the end");
    Scene s;
    ASSERT_TRUE(readObj(path, s));
    const TriangleMesh& m = s.meshes[0];
    EXPECT_EQ(m.vertexCount(), 5u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 1, 2, 4, 2, 3, 4, 3, 0}));
    EXPECT_TRUE(m.normals.empty());

    std::string withAttributes = test::writeFile(dir / "attributes.obj",
                                                 "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                 "vt 0 0\nvt 1 0\nvt 0 1\n"
                                                 "vn 0 0 1\nvn 0 0 1\nvn 0 0.6 0.8\n"
                                                 "f 1/1/1 2/2/2 3/3/3\n");
    Scene a;
    ASSERT_TRUE(readObj(withAttributes, a));
    EXPECT_EQ(a.meshes[0].normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0.6f, 0.8f}));
    EXPECT_EQ(a.meshes[0].uvs, (std::vector<float>{0, 0, 1, 0, 0, 1}));
    std::string normalsOnly = test::writeFile(dir / "normals.obj",
                                              "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                              "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
                                              "f 1//1 2//2 3//3\n");
    Scene n;
    ASSERT_TRUE(readObj(normalsOnly, n));
    EXPECT_EQ(n.meshes[0].normals.size(), 9u);
    EXPECT_TRUE(n.meshes[0].uvs.empty());
}

TEST(ObjReader, GroupsBecomeMeshesAsInAssimp) {
    auto dir = test::scratchDir();
    std::string path = test::writeFile(dir / "groups.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "f 1 2 3\n"
                                       "o first\nf 1 3 4\n"
                                       "v 0 0 1\nv 1 0 1\nv 1 1 1\n"
                                       "g  second group\nf 5 6 7\nf -1 -2 -3\n"
                                       "g empty\n");
    Scene direct, viaAssimp;
    ASSERT_TRUE(readObj(path, direct));
    importWithAssimp(path, nullptr, viaAssimp);
    ASSERT_EQ(direct.meshes.size(), 3u);
    ASSERT_EQ(viaAssimp.meshes.size(), 3u);
    for (size_t m = 0; m < 3; ++m) {
        EXPECT_EQ(direct.meshes[m].name, viaAssimp.meshes[m].name);
        Scene a, b;
        a.meshes = {direct.meshes[m]}, b.meshes = {viaAssimp.meshes[m]};
        EXPECT_EQ(cornerPositions(a), cornerPositions(b)) << m;
    }
    // Each group keeps only its own vertex block.
    EXPECT_EQ(direct.meshes[2].vertexCount(), 3u);
    EXPECT_EQ(direct.meshes[2].indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}));
}

TEST(ObjReader, ChunkBoundariesAndRelativeIndicesAcrossChunks) {
    // About 12 MB: several 4 MB chunks, each face written with relative indices so a wrong
    // per-chunk vertex offset shows up as a wrong triangle.
    auto dir = test::scratchDir();
    TriangleMesh grid = test::gridMesh(500, 500, 0.25f);
    // Each face right after the last vertex it uses, with indices relative to the count so far.
    std::vector<std::vector<size_t>> facesAfter(grid.vertexCount());
    for (size_t t = 0; t < grid.triangleCount(); ++t) {
        const uint32_t* idx = &grid.indices[3 * t];
        facesAfter[std::max({idx[0], idx[1], idx[2]})].push_back(t);
    }
    std::string text;
    for (size_t v = 0; v < grid.vertexCount(); ++v) {
        Vec3 p = grid.vertex(uint32_t(v));
        text += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) +
                "\n";
        for (size_t t : facesAfter[v]) {
            const uint32_t* idx = &grid.indices[3 * t];
            text += "f";
            // Appended piece by piece: " " + std::to_string(...) draws a false -Wrestrict from
            // GCC 12.
            for (int k = 0; k < 3; ++k) {
                text += ' ';
                text += std::to_string(int64_t(idx[k]) - int64_t(v) - 1);
            }
            text += "\n";
        }
    }
    ASSERT_GT(text.size(), 3u << 22);
    std::string path = test::writeFile(dir / "grid.obj", text);
    Scene s;
    ASSERT_TRUE(readObj(path, s));
    ASSERT_EQ(s.meshes[0].triangleCount(), grid.triangleCount());
    // Same triangles as a set (the file lists them in a different order).
    auto key = [](const uint32_t* t) {
        std::array<uint32_t, 3> k = {t[0], t[1], t[2]};
        std::sort(k.begin(), k.end());
        return k;
    };
    std::vector<std::array<uint32_t, 3>> want, got;
    for (size_t t = 0; t < grid.triangleCount(); ++t) {
        want.push_back(key(&grid.indices[3 * t]));
        got.push_back(key(&s.meshes[0].indices[3 * t]));
    }
    std::sort(want.begin(), want.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(want, got);
}

TEST(ObjReader, WhatItDoesNotHandleGoesToAssimp) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "red.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
    std::string withMaterial = test::writeFile(
        dir / "material.obj", "mtllib red.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    Scene direct;
    EXPECT_FALSE(readObj(withMaterial, direct));
    EXPECT_TRUE(direct.meshes.empty() && direct.materials.empty());
    Scene loaded = loadScene(withMaterial);
    bool red = false;
    for (const Material& m : loaded.materials) red |= m.name == "red" && m.albedo.x > 0.7f;
    EXPECT_TRUE(red) << "the .mtl material should arrive through Assimp";

    // Normal indices that differ from position indices need vertex splitting: Assimp's job.
    std::string split = test::writeFile(dir / "split.obj",
                                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                        "vn 0 0 1\nvn 0 0 -1\n"
                                        "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n");
    Scene s;
    EXPECT_FALSE(readObj(split, s));
    Scene viaLoader = loadScene(split);
    EXPECT_EQ(viaLoader.uniqueTriangles(), 2u);
}

TEST(ObjReader, BadInputNamesFileAndLine) {
    auto dir = test::scratchDir();
    struct Case {
        const char* text;
        const char* expect;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: vertex index 4 out of range"},
        {"v 0 0 0\nv 1 zero 0\n", "line 2: 'zero' is not a number"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: face with fewer than 3 vertices"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: vertex index 0 out of range"},
        {"# nothing\nf 1 2 3\n", "has no vertices"},
    };
    for (const Case& c : cases) {
        test::expectError(test::writeFile(dir / "bad.obj", c.text), c.expect);
    }
}

// Issue #33 item 4: files kiln's reader hands to Assimp (normal or uv counts that differ from the
// vertex count, materials, lines) have every index checked against the file's own counts; Assimp
// 5.2 gave a face whose normal index is past the last 'vn' another normal, and said nothing.
TEST(ObjReader, EveryIndexIsCheckedWhicheverReaderReadsTheFile) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "red.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
    struct Case {
        std::string text;
        const char* expect;
    } cases[] = {
        // Two normals for four vertices: Assimp's case; the second face names normal 3.
        {quad + "vn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 2//2 4//3 3//2\n",
         "line 8: normal index 3 out of range (2 'vn' normals in the file)"},
        {quad + "vn 0 0 1\nf 1//1 2//1 3//1\nf 2//-2 4//1 3//1\n",
         "line 7: normal index -2 out of range (1 'vn' normals before it)"},
        {quad + "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 2/2 4/4 3/3\n",
         "line 9: texture coordinate index 4 out of range (3 'vt' texture coordinates"},
        {"mtllib red.mtl\n" + quad + "usemtl red\nf 1 2 3\nf 2 5 3\n",
         "line 8: vertex index 5 out of range (4 'v' vertices in the file)"},
        {"mtllib red.mtl\n" + quad + "usemtl red\nf 1 2 3\nl 1 9\n",
         "line 8: vertex index 9 out of range"},
        {"mtllib red.mtl\n" + quad + "usemtl red\nf 1 2 x3\n", "line 7: bad vertex index 'x3'"},
    };
    for (const Case& c : cases)
        test::expectError(test::writeFile(dir / "bad.obj", c.text), c.expect);
    // The same files with their indices in range load through Assimp.
    Scene normals = loadScene(test::writeFile(
        dir / "good.obj", quad + "vn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 2//2 4//2 3//-1\n"));
    EXPECT_EQ(normals.uniqueTriangles(), 2u);
    Scene material = loadScene(test::writeFile(
        dir / "good_mtl.obj", "mtllib red.mtl\n" + quad + "usemtl red\nf 1 2 3\nf -3 -1 -2\n"));
    EXPECT_EQ(material.uniqueTriangles(), 2u);
}

TEST(ObjReader, MemoryEstimateRefusesBeforeAllocating) {
    test::ScopedMemoryLimit limit("1000000");  // 1 MB
    try {
        loadScene(test::shared("meshes/lucy.obj"));
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("would need about"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("99970 faces"), std::string::npos) << e.what();
    }
}

TEST(ObjReader, WriterRoundTrips) {
    auto dir = test::scratchDir();
    TriangleMesh grid = test::gridMesh(7, 5, 0.3f);
    std::string path = (dir / "grid.obj").string();
    writeObj(path, grid);
    Scene s;
    ASSERT_TRUE(readObj(path, s));
    EXPECT_EQ(s.meshes[0].indices, grid.indices);
    std::vector<float> got(s.meshes[0].positions.begin(),
                           s.meshes[0].positions.begin() + long(3 * grid.vertexCount()));
    std::vector<float> want(grid.positions.begin(),
                            grid.positions.begin() + long(3 * grid.vertexCount()));
    EXPECT_EQ(got, want);  // shortest round-trip floats: exact
}

}  // namespace
}  // namespace kiln
