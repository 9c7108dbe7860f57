// Bad input: a one-line SceneError naming the file and the problem, never a crash.
#include <cstring>
#include <fstream>
#include <iterator>
#include <tuple>

#include "renderer/geometry/camera.h"
#include "scene/cgl_extras.h"
#include "scene/scene_error.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

using test::expectError;

// A minimal valid COLLADA scene; tests break one piece of it at a time.
std::string collada(const std::string& effectExtra,
                    const std::string& positions = "0 0 0 1 0 0 0 1 0",
                    const std::string& indices = "0 1 2", const std::string& lights = "") {
    return R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><up_axis>Y_UP</up_axis></asset>
<library_lights>)" +
           lights + R"(</library_lights>
<library_effects><effect id="e"><profile_COMMON><technique sid="common"><phong><diffuse><color>0.5 0.5 0.5 1</color></diffuse></phong></technique></profile_COMMON>)" +
           effectExtra + R"(</effect></library_effects>
<library_materials><material id="m" name="m"><instance_effect url="#e"/></material></library_materials>
<library_geometries><geometry id="g" name="g"><mesh>
<source id="p"><float_array id="pa" count="9">)" +
           positions + R"(</float_array>
<technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles material="m" count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>)" +
           indices + R"(</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
<instance_geometry url="#g"><bind_material><technique_common><instance_material symbol="m" target="#m"/></technique_common></bind_material></instance_geometry></node>
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>
)";
}

TEST(BadInput, MissingFile) { expectError("/nonexistent/scene.dae", "no such file"); }

TEST(BadInput, Directory) { expectError(test::scratchDir().string(), "directory"); }

TEST(BadInput, EmptyFile) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "empty.dae", ""), "empty");
}

TEST(BadInput, UnreadableFormat) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "junk.obj", "this is not a mesh\n\x01\x02\x03"), "");
}

TEST(BadInput, MalformedXml) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "broken.dae", "<COLLADA><asset></COLLADA>"), "malformed XML");
}

TEST(BadInput, GarbledCglValue) {
    auto dir = test::scratchDir();
    std::string extra =
        R"(<extra><technique profile="CGL"><glass><reflectance>1 1 1</reflectance><transmittance>1 one 1</transmittance><roughness>0</roughness><ior>1.5</ior></glass></technique></extra>)";
    expectError(test::writeFile(dir / "garbled.dae", collada(extra)), "garbled number");
}

TEST(BadInput, MissingCglValue) {
    auto dir = test::scratchDir();
    std::string extra =
        R"(<extra><technique profile="CGL"><glass><reflectance>1 1 1</reflectance><roughness>0</roughness><ior>1.5</ior></glass></technique></extra>)";
    expectError(test::writeFile(dir / "missing.dae", collada(extra)), "missing <transmittance>");
}

TEST(BadInput, UnknownMaterial) {
    auto dir = test::scratchDir();
    std::string extra =
        R"(<extra><technique profile="CGL"><velvet><sheen>1</sheen></velvet></technique></extra>)";
    expectError(test::writeFile(dir / "unknown.dae", collada(extra)),
                "unknown CGL material <velvet>");
}

TEST(BadInput, NanVertexInCollada) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "nan.dae", collada("", "0 0 0 nan 0 0 0 1 0")), "non-finite");
}

TEST(BadInput, NanVertexInObj) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
                "non-finite");
}

TEST(BadInput, InfVertexInPly) {
    auto dir = test::scratchDir();
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
        "float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\ninf 0 0\n0 1 "
        "0\n3 0 1 2\n";
    expectError(test::writeFile(dir / "inf.ply", ply), "non-finite");
}

TEST(BadInput, IndexOutOfRangeInPly) {
    auto dir = test::scratchDir();
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
        "float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 "
        "0\n3 0 1 7\n";
    expectError(test::writeFile(dir / "range.ply", ply), "out of range");
}

TEST(BadInput, TruncatedBinaryPly) {
    auto dir = test::scratchDir();
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
        "y\n"
        "property float z\nend_header\n\x01\x02";
    expectError(test::writeFile(dir / "short.ply", ply), "file ends before");
}

TEST(BadInput, IndexOutOfRangeInObjIsRejected) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "");
}

TEST(BadInput, EmptyScene) {
    auto dir = test::scratchDir();
    std::string empty =
        R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset><library_visual_scenes><visual_scene id="s"/></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)";
    expectError(test::writeFile(dir / "empty_scene.dae", empty), "");
}

TEST(BadInput, SceneWithoutLightsWarnsAndGetsTheDefaultRig) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(dir / "dark.dae", collada("")));
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_NE(s.warnings[0].find("no lights"), std::string::npos);
    EXPECT_EQ(s.lights.size(), 2u);
}

// The minimal scene with one point light of this colour, placed by its own node.
std::string colladaWithPointLight(const std::string& color) {
    std::string text = collada("", "0 0 0 1 0 0 0 1 0", "0 1 2",
                               R"(<light id="l"><technique_common><point><color>)" + color +
                                   "</color></point></technique_common></light>");
    text.replace(text.find("</visual_scene>"), 0,
                 R"(<node id="ln"><instance_light url="#l"/></node>)");
    return text;
}

TEST(BadInput, NegativeLightRadiance) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "neg.dae", colladaWithPointLight("-1 1 1")),
                "negative radiance");
}

TEST(BadInput, MissingEnvironmentMap) {
    LoadOptions o;
    o.environmentMap = "/nonexistent/sky.exr";
    try {
        loadScene(test::shared("meshes/stanford-bunny.obj"), o);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/sky.exr: no such environment map"),
                  std::string::npos);
    }
}

TEST(BadInput, UnreadableEnvironmentMap) {
    auto dir = test::scratchDir();
    LoadOptions o;
    o.environmentMap = test::writeFile(dir / "sky.exr", "not an image at all");
    try {
        loadScene(test::shared("meshes/stanford-bunny.obj"), o);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot read environment map"), std::string::npos)
            << e.what();
    }
}

// The --env map is read before the scene's import: a malformed map is refused first, not after a
// 100M-triangle import. The scene here is malformed too, so the error tells which was read first.
TEST(BadInput, AMalformedEnvironmentMapIsRefusedBeforeTheImport) {
    auto dir = test::scratchDir();
    const std::string mesh =
        test::writeFile(dir / "broken.ply", "ply\nformat ascii 1.0\nend_header\n");
    LoadOptions o;
    EXPECT_THROW(loadScene(mesh, o), SceneError);  // the control: the scene alone is refused
    o.environmentMap = test::writeFile(dir / "sky.exr", "not an image at all");
    try {
        loadScene(mesh, o);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("sky.exr: cannot read environment map"),
                  std::string::npos)
            << e.what();
    }
}

// What a PLY header alone decides is refused before any row is read: here a 100M-row element comes
// first and the file holds none of its rows, so a reader that got to the vertices first would say
// the file ends early (and on a real file, after reading them all).
TEST(BadInput, PlyHeaderMistakesAreRefusedBeforeAnyRow) {
    auto dir = test::scratchDir();
    const std::string junk = "ply\nformat ascii 1.0\nelement junk 100000000\nproperty float a\n";
    expectError(
        test::writeFile(dir / "noz.ply", junk + "element vertex 3\nproperty float x\nproperty "
                                                "float y\nend_header\n"),
        "PLY vertex element lacks x, y or z");
    expectError(test::writeFile(dir / "novertex.ply", junk + "end_header\n"),
                "PLY has no vertex element");
    expectError(test::writeFile(dir / "many.ply", junk + "element vertex 100000000\nproperty float "
                                                         "x\nproperty float y\nproperty float "
                                                         "z\nend_header\n"),
                "more than the file can hold");
}

// A CGL sphere bound to a material the file lacks is refused by kiln's XML pass, which runs before
// Assimp imports the file's meshes (it was found only after them).
TEST(BadInput, ASphereBoundToAnUnknownMaterialIsRefusedBeforeAssimp) {
    auto dir = test::scratchDir();
    std::ifstream in(test::cs184("sky/CBspheres_lambertian.dae"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = R"(target="#refract")";
    ASSERT_NE(text.find(from), std::string::npos);
    text.replace(text.find(from), from.size(), R"(target="#nope")");
    const std::string path = test::writeFile(dir / "sphere.dae", text);
    const char* what = "sphere 'Sphere1' binds unknown material 'nope'";
    try {
        parseColladaExtras(path);
        ADD_FAILURE() << "the XML pass let it through";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    expectError(path, what);
}

// A garbled COLLADA count or index list is refused by kiln's XML pass before Assimp (which
// dereferences null or allocates without bound on them) ever sees it.
TEST(BadInput, GarbledColladaCountsNeverReachAssimp) {
    auto dir = test::scratchDir();
    std::string good = collada("");
    for (auto [from, to, what] : {
             std::tuple{R"(count="9">)", R"(count="0">)", "holds 9 numbers"},
             std::tuple{R"(count="9">)", R"(count="">)", "not a non-negative integer"},
             std::tuple{R"(count="9">)", R"(count="-6">)", "not a non-negative integer"},
             std::tuple{R"(count="9">)", R"(count="abc">)", "not a non-negative integer"},
             std::tuple{R"(count="3" stride="3")", R"(count="30" stride="3")", "reads 90 values"},
             std::tuple{"<p>0 1 2</p>", "<p>0 1 -1e39</p>", "not a non-negative integer"},
             std::tuple{"<p>0 1 2</p>", "<p>0 1 2.5</p>", "not a non-negative integer"},
         }) {
        std::string text = good;
        ASSERT_NE(text.find(from), std::string::npos) << from;
        text.replace(text.find(from), std::string(from).size(), to);
        expectError(test::writeFile(dir / "garbled_count.dae", text), what);
    }
}

TEST(BadInput, StrictAsciiPlyNumbers) {
    auto dir = test::scratchDir();
    auto ply = [](const std::string& faceCount, const std::string& face) {
        return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nelement face " +
               faceCount +
               "\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n" +
               face + "\n";
    };
    EXPECT_NO_THROW(loadScene(test::writeFile(dir / "ok.ply", ply("1", "3 0 1 2"))));
    for (auto [count, face, what] : {
             std::tuple{"1,5", "3 0 1 2", "malformed PLY element line"},
             std::tuple{"1x", "3 0 1 2", "malformed PLY element line"},
             std::tuple{"-1", "3 0 1 2", "malformed PLY element line"},
             std::tuple{"1", "3 0 1 2.7", "non-integer"},
             std::tuple{"1", "3.9 0 1 2", "non-integer"},
             std::tuple{"1", "3 0 1x 2", "garbled number"},
         })
        expectError(test::writeFile(dir / "strict.ply", ply(count, face)), what);
}

// glTF: 3 vertices, indices 0 1 5. Assimp drops such faces with only a log line.
TEST(BadInput, GltfIndexOutOfRange) {
    auto dir = test::scratchDir();
    std::string bin(44, '\0');
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint16_t idx[4] = {0, 1, 5, 0};
    std::memcpy(bin.data(), pos, 36);
    std::memcpy(bin.data() + 36, idx, 8);
    test::writeFile(dir / "buf.bin", bin);
    std::string gltf =
        R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 44, "uri": "buf.bin"}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
    expectError(test::writeFile(dir / "range.gltf", gltf), "out of range");
}

TEST(BadInput, KilnSceneMistakesAreErrors) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    // Each mistake again after a part whose import fails: every element is checked before the
    // first part is imported, so the mistake is what is named (not a minute into a 100M-triangle
    // import, which this broken part stands for).
    test::writeFile(dir / "broken.ply", "ply\nformat ascii 1.0\nend_header\n");
    test::writeFile(dir / "empty.obj", "");
    // An override file is checked, not imported, before the parts: its broken mesh would be named.
    test::writeFile(
        dir / "mats.kiln",
        R"(<kiln-scene><material name="gold" albedo="0.8 0.6 0.2"/><mesh file="broken.ply"/></kiln-scene>)");
    // Files that settle their material names themselves (no part could bring another).
    test::writeFile(dir / "only_mats.kiln",
                    R"(<kiln-scene><material name="gold" albedo="0.8 0.6 0.2"/></kiln-scene>)");
    test::writeFile(dir / "no_mats.kiln", "<kiln-scene/>");
    const std::string longName(300, 'x');  // too long for the file system: not there, no exception
    test::writeFile(dir / "nested.kiln",
                    R"(<kiln-scene><mesh file="tri.obj"/><bogus/></kiln-scene>)");
    std::filesystem::create_directories(dir / "adir");
    expectError(test::writeFile(dir / "first.kiln",
                                R"(<kiln-scene><mesh file="broken.ply"/></kiln-scene>)"),
                "broken.ply");
    for (const char* before : {"", R"(<mesh file="broken.ply"/>)"})
        for (
            auto [body, what] : {
                std::pair{R"(<mesh file="tri.obj" translat="1 0 0"/>)",
                          "unknown attribute 'translat'"},
                std::pair{R"(<mesh file="tri.obj"><fitt center="0 0 0" size="1"/></mesh>)",
                          "unknown element <fitt>"},
                std::pair{
                    R"(<mesh file="tri.obj"/><camera position="0 0 5" look-at="0 0 0" fov="0"/>)",
                    "fov must be between 0 and 180"},
                std::pair{
                    R"(<mesh file="tri.obj"/><camera position="0 0 5" look-at="0 0 0" fov="180"/>)",
                    "fov must be between 0 and 180"},
                std::pair{
                    R"(<mesh file="tri.obj"/><camera position="0 0 5" look-at="0 0 0" fov="-30"/>)",
                    "fov must be between 0 and 180"},
                std::pair{
                    R"(<mesh file="tri.obj"/><camera position="1 2 3" look-at="1 2 3" fov="40"/>)",
                    "are the same point"},
                std::pair{R"(<instances file="tri.obj" grid="100000 100000 100000" spacing="1"/>)",
                          "would need about"},
                std::pair{R"(<instances file="tri.obj" grid="2.5 1 1" spacing="1"/>)",
                          "whole numbers"},
                std::pair{R"(<mesh file="missing.ply"/>)", "missing.ply: no such file"},
                std::pair{R"(<light kind="spot" radiance="1 1 1"/>)", "unknown light kind 'spot'"},
                std::pair{R"(<mesh file="tri.obj"><override material="nope"/></mesh>)",
                          "unknown material 'nope'"},
                std::pair{R"(<mesh file="tri.obj"><matrix values="1 0 0"/></mesh>)",
                          "values needs 16 numbers"},
                std::pair{R"(<mesh file="tri.obj"><override spec="claay"/></mesh>)",
                          "claay: not a material override"},
                std::pair{R"(<mesh file="adir"/>)", "adir: is a directory"},
                std::pair{R"(<mesh file="empty.obj"/>)", "empty.obj: file is empty"},
                std::pair{R"(<include file="bad.kiln"/>)", "include cycle"},
                std::pair{
                    R"(<mesh file="tri.obj"><override spec="mats.kiln:gold"/></mesh><mesh file="missing.ply"/>)",
                    "missing.ply: no such file"},
                std::pair{R"(<include file="nested.kiln"/>)",
                          "nested.kiln: unknown element <bogus>"},
                std::pair{R"(<mesh file="tri.obj"><override spec="only_mats.kiln:silver"/></mesh>)",
                          "has no material named 'silver'"},
                std::pair{R"(<mesh file="tri.obj"><override spec="no_mats.kiln"/></mesh>)",
                          "has no <material>"},
            }) {
            std::string path = test::writeFile(
                dir / "bad.kiln", std::string("<kiln-scene>") + before + body + "</kiln-scene>");
            expectError(path, what);
        }
    expectError(
        test::writeFile(dir / "long.kiln", "<kiln-scene><mesh file=\"tri.obj\"><override spec=\"" +
                                               longName + "\"/></mesh></kiln-scene>"),
        "not a material override");
}

TEST(BadInput, KilnIncludeCycleIsAnError) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string self = test::writeFile(
        dir / "self.kiln",
        R"(<kiln-scene><mesh file="tri.obj"/><include file="self.kiln"/></kiln-scene>)");
    expectError(self, "include cycle");
    test::writeFile(dir / "a.kiln", R"(<kiln-scene><include file="b.kiln"/></kiln-scene>)");
    test::writeFile(dir / "b.kiln", R"(<kiln-scene><include file="a.kiln"/></kiln-scene>)");
    expectError((dir / "a.kiln").string(), "include cycle");
}

TEST(BadInput, OnlyZeroAreaTrianglesIsAnError) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
                "every triangle has zero area");
    // One such mesh beside a visible one: a warning naming it.
    Scene s = loadScene(test::writeFile(
        dir / "mixed.obj",
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\no line\nf 1 2 3\no visible\nf 1 2 4\n"));
    bool warned = false;
    for (const std::string& w : s.warnings)
        warned |= w.find("'line': all 1 triangles have zero area") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(BadInput, ZeroPowerFileLightsWarnAndInfoSaysSo) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(dir / "zero.dae", colladaWithPointLight("0 0 0")));
    std::string info = sceneInfoText(s);
    EXPECT_NE(info.find("has zero power"), std::string::npos) << info;
    EXPECT_NE(info.find("every light has zero power"), std::string::npos) << info;
}

TEST(BadInput, InvalidCameraIsRefusedBeforeAnyRay) {
    Camera c;
    c.forward = Vec3(0.0f);
    EXPECT_THROW(validateCamera("x", c), SceneError);
    c = Camera{};
    c.hFovDeg = 180;
    EXPECT_THROW(validateCamera("x", c), SceneError);
    c = Camera{};
    c.position = Vec3(std::nanf(""), 0, 0);
    EXPECT_THROW(CameraModel(c, 8, 8), SceneError);
    EXPECT_NO_THROW(CameraModel(Camera{}, 8, 8));
}

TEST(BadInput, SceneSpanningBeyondFloatIsRefused) {
    auto dir = test::scratchDir();
    expectError(test::writeFile(dir / "huge.obj",
                                "v -1e18 0 0\nv 1e18 0 0\nv 0 1e18 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n"),
                "kiln traces at most");
}

// Assimp's OFF reader loops over the counts its header declares (minutes for this one, from
// assimp-testmodels' invalid/OutOfMemory.off).
TEST(BadInput, OffHeaderBeyondTheFileIsRefused) {
    auto dir = test::scratchDir();
    expectError(
        test::writeFile(dir / "huge.off",
                        "OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n0.5 -0.5 0.5\n-0.5 0.5 0.5\n"),
        "353535235358 vertices, more than the file can hold");
    expectError(test::writeFile(dir / "neg.off", "OFF\n-3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                "not a non-negative integer");
    Scene ok =
        loadScene(test::writeFile(dir / "ok.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_EQ(ok.uniqueTriangles(), 1u);
}

}  // namespace
}  // namespace kiln
