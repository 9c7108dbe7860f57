// Cameras, lights and materials read through Assimp and the COLLADA pass, each compared with the
// value written in a file the test writes itself.
#include <filesystem>

#include "renderer/accel/accelerator.h"
#include "renderer/exr_scene.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// A one-triangle glTF 2.0 scene (base64 buffer) with this camera on a node at (0.5, 0.5, 3).
std::string gltfWithCamera(const std::string& camera) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"translation": [0.5, 0.5, 3.0], "camera": 0}], "cameras": [)" +
           camera +
           R"(], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

Scene loadAsFile(const std::string& path) {
    LoadOptions o;
    o.cameraRule = LoadOptions::CameraRule::File;
    return loadScene(path, o);
}

// yfov 0.7 rad (40.107 degrees) at aspect 1.5, node at (0.5, 0.5, 3): Assimp reports
// mHorizontalFOV = yfov * aspect and copies the node's translation into mPosition.
TEST(ImportCameras, GltfFieldOfViewAndPositionAsWritten) {
    auto dir = test::scratchDir();
    Scene s = loadAsFile(test::writeFile(
        dir / "cam.gltf",
        gltfWithCamera(
            R"({"type": "perspective", "perspective": {"aspectRatio": 1.5, "yfov": 0.7, "zfar": 100, "znear": 0.01}})")));
    ASSERT_TRUE(s.hasFileCamera);
    EXPECT_NEAR(s.camera.vFovDeg, 0.7 * 180 / 3.14159265358979, 1e-3);
    EXPECT_NEAR(s.camera.hFovDeg, 2 * std::atan(std::tan(0.35) * 1.5) * 180 / 3.14159265358979,
                1e-3);
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(p.x, 0.5, 1e-6);
    EXPECT_NEAR(p.y, 0.5, 1e-6);
    EXPECT_NEAR(p.z, 3.0, 1e-6);
    EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-6f);
    EXPECT_NEAR(s.camera.nearClip, 0.01f, 1e-7f);
}

std::string centimetreCollada(bool withLight);

// A unit quad [0,1]^2 at z = 0 seen by this camera from a node at (0.5, 0.5, 3).
std::string gltfQuadWithCamera(const std::string& camera) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"translation": [0.5, 0.5, 3.0], "camera": 0}], "cameras": [)" +
           camera +
           R"(], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAAAAABAAIAAAACAAMA"}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
}

// Which pixels of a w x h render see a surface (albedo AOV non-zero).
std::vector<std::vector<bool>> coverage(const Scene& s, int w, int h) {
    AovRequest aovs;
    aovs.add(AovKind::Albedo);
    auto accel = makeEmbreeAccelerator(s);
    Film f = test::renderJob(s, *accel, test::jobOptions(w, h, 4, PathOptions{}, aovs));
    size_t r = test::aovChannel(f, "albedo.R");
    std::vector<std::vector<bool>> hit(size_t(h), std::vector<bool>(size_t(w), false));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) hit[size_t(y)][size_t(x)] = f.aov(x, y, r) > 0;
    return hit;
}

// glTF orthographic xmag = ymag = 1 (half extents): the view spans [-0.5, 1.5] vertically; at
// 96 x 64 the width widens to 3 units (the aspect fit), 32 pixels per unit, so the quad covers
// exactly columns 32..63 and rows 16..47 (pixel edges fall on the quad's edges).
TEST(ImportCameras, OrthographicViewOfAUnitQuadCoversItsPixelExtent) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(
        dir / "ortho.gltf",
        gltfQuadWithCamera(
            R"({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "zfar": 100, "znear": 0.01}})")));
    ASSERT_TRUE(s.hasFileCamera);
    ASSERT_TRUE(s.camera.orthographic());
    EXPECT_FLOAT_EQ(s.camera.orthoHalfWidth, 1.0f);
    EXPECT_FLOAT_EQ(s.camera.orthoHalfHeight, 1.0f);
    auto hit = coverage(s, 96, 64);
    int wrong = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            bool expected = x >= 32 && x < 64 && y >= 16 && y < 48;
            wrong += hit[size_t(y)][size_t(x)] != expected;
        }
    EXPECT_EQ(wrong, 0);
    // The EXR's worldToNDC (row vectors) maps the quad's corners to the same pixel edges.
    std::array<float, 16> m = exrCamera(s, test::jobOptions(96, 64, 1).settings).worldToNDC;
    for (auto [wx, wy, nx, ny] : {std::array<float, 4>{0, 0, 32.0f / 96, 48.0f / 64},
                                  std::array<float, 4>{1, 1, 64.0f / 96, 16.0f / 64}}) {
        float x = wx * m[0] + wy * m[4] + m[12], y = wx * m[1] + wy * m[5] + m[13],
              w = wx * m[3] + wy * m[7] + m[15];
        EXPECT_NEAR(x / w, nx, 1e-6f);
        EXPECT_NEAR(y / w, ny, 1e-6f);
    }
}

// xmag 2, ymag 1: Assimp reports mOrthographicWidth = xmag and mAspect = xmag / ymag.
TEST(ImportCameras, OrthographicGltfKeepsBothMagnifications) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(
        dir / "ortho.gltf",
        gltfQuadWithCamera(
            R"({"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0, "zfar": 100, "znear": 0.01}})")));
    EXPECT_FLOAT_EQ(s.camera.orthoHalfWidth, 2.0f);
    EXPECT_FLOAT_EQ(s.camera.orthoHalfHeight, 1.0f);
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(p.z, 3.0, 1e-6);
}

// COLLADA <orthographic> in a Z-up file (where the CS184 rule would move a perspective camera):
// xmag 50 cm with aspect 2 is half a metre wide and a quarter high, and the camera stays where the
// file puts it.
TEST(ImportCameras, ColladaOrthographicIsScaledAndNotReframed) {
    auto dir = test::scratchDir();
    std::string dae = centimetreCollada(false);
    auto replace = [&](const std::string& from, const std::string& to) {
        size_t at = dae.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        dae.replace(at, from.size(), to);
    };
    replace("<perspective><yfov>40</yfov><aspect_ratio>1</aspect_ratio>",
            "<orthographic><xmag>50</xmag><aspect_ratio>2</aspect_ratio>");
    replace("</perspective>", "</orthographic>");
    replace("<up_axis>Y_UP</up_axis>", "<up_axis>Z_UP</up_axis>");
    Scene s = loadScene(test::writeFile(dir / "ortho.dae", dae));
    ASSERT_TRUE(s.camera.orthographic());
    EXPECT_FALSE(s.framedByCourseRule);
    EXPECT_NEAR(s.camera.orthoHalfWidth, 0.5f, 1e-6f);
    EXPECT_NEAR(s.camera.orthoHalfHeight, 0.25f, 1e-6f);
    EXPECT_NEAR(s.camera.nearClip, 0.1f, 1e-7f);
    // Node (0, 50, 500) cm in Z-up: the course matrix maps it to (0, 5, 0.5) m.
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(std::abs(p.y) + std::abs(p.z), 5.5, 1e-5);
    // Asking for the course rule explicitly is answered with a warning, not a moved camera.
    LoadOptions framed;
    framed.cameraRule = LoadOptions::CameraRule::Framed;
    std::string path = (dir / "ortho.dae").string();
    Scene f = loadScene(path, framed);
    EXPECT_TRUE(test::hasWarning(f, "CS184 framing rule does not apply"));
    EXPECT_NEAR(f.world(f.camera.position).x, p.x, 1e-6);
}

// 3DS: Assimp 5.2 drops the target and reads the lens as an angle. TargetCameraAnim.3ds states
// position (-65.8677, 16.1213, -2.42502), target (100.410, 28.2159, 0), lens 53.333 (= 2400 / 45)
// in Z-up coordinates, which Assimp's root node turns to Y-up: (x, z, -y).
TEST(ImportCameras, ThreeDsCameraAsTheFileStatesIt) {
    std::string path = "/usr/share/assimp/models/3DS/TargetCameraAnim.3ds";
    ASSERT_TRUE(std::filesystem::exists(path)) << "assimp-testmodels (tools/setup.sh) missing";
    Scene s = loadAsFile(path);
    ASSERT_TRUE(s.hasFileCamera);
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(p.x, -65.8677, 1e-3);
    EXPECT_NEAR(p.y, -2.42502, 1e-3);
    EXPECT_NEAR(p.z, -16.1213, 1e-3);
    Vec3 toTarget = normalize(Vec3(Vec3d(100.41005, 0.0, -28.215897) - p));
    EXPECT_GT(dot(s.camera.forward, toTarget), 0.99999f);
    EXPECT_NEAR(s.camera.hFovDeg, 45.0f, 1e-3f);
    EXPECT_NEAR(s.camera.up.y, 1.0f, 1e-6f);  // bank 0: the file's +Z
}

// OpenGEX from Blender: the camera matrix is Blender's, whose -Z is the view (default scene: camera
// at (7.48, -6.51, 5.34) looking at the cube at the origin). Assimp reports +Z.
TEST(ImportCameras, OpenGexCameraLooksAtTheScene) {
    auto dir = test::scratchDir();
    Scene s = loadAsFile(test::writeFile(dir / "cam.ogex", R"(Metric (key = "up") {string {"z"}}
GeometryNode $node1 { Name {string {"Tri"}} ObjectRef {ref {$geometry1}}
  Transform { float[16] { {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1} } } }
CameraNode $node2 { Name {string {"Camera"}} ObjectRef {ref {$camera1}}
  Transform { float[16] { {0.6858805, 0.7276338, -0.0108168, 0.0,
    -0.3173701, 0.3124686, 0.8953433, 0.0, 0.6548619, -0.6106656, 0.4452454, 0.0,
    7.4811316, -6.5076399, 5.3436651, 1.0} } } }
GeometryObject $geometry1 { Mesh (primitive = "triangles") {
  VertexArray (attrib = "position") { float[3] { {-1, -1, 0}, {1, -1, 0}, {0, 1, 0} } }
  IndexArray { unsigned_int32[3] { {0, 1, 2} } } } }
CameraObject $camera1 { Param (attrib = "fov") {float {0.857556}} }
)"));
    ASSERT_TRUE(s.hasFileCamera);
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(p.x, 7.4811316, 1e-4);
    Vec3 toOrigin = normalize(Vec3(-p));
    EXPECT_GT(dot(s.camera.forward, toOrigin), 0.99f);
}

// NFF states the full angle ("angle 60") and a from/at pair.
TEST(ImportCameras, NffAngleIsTheFullHorizontalAngle) {
    auto dir = test::scratchDir();
    Scene s = loadAsFile(test::writeFile(
        dir / "cam.nff",
        "v\nfrom 0 3 10\nat 0 0 0\nup 0 1 0\nangle 60\nhither 0.1\nresolution 640 480\n\n"
        "f 1 0 0 0.8 .8 20 0 1\np 3\n-1 -1 0\n1 -1 0\n0 1 0\n"));
    ASSERT_TRUE(s.hasFileCamera);
    EXPECT_NEAR(s.camera.hFovDeg, 60.0f, 1e-3f);
    Vec3d p = s.world(s.camera.position);
    EXPECT_NEAR(p.y, 3.0, 1e-5);
    EXPECT_NEAR(p.z, 10.0, 1e-5);
    Vec3 toOrigin = normalize(Vec3(-Vec3(p)));
    EXPECT_GT(dot(s.camera.forward, toOrigin), 0.9999f);
}

// ASE and LWS cameras look down their node's -Z; Assimp reports +Z. Their cameras in Assimp's
// own test files must look at the scene.
TEST(ImportCameras, AseAndLwsCamerasLookAtTheScene) {
    for (const char* rel : {"ASE/CameraRollAnim.ase", "LWS/move_x.lws"}) {
        std::string path = std::string("/usr/share/assimp/models/") + rel;
        ASSERT_TRUE(std::filesystem::exists(path)) << "assimp-testmodels (tools/setup.sh) missing";
        Scene s = loadAsFile(path);
        ASSERT_TRUE(s.hasFileCamera) << rel;
        Bounds3 b = s.storedBounds();
        Vec3 toScene = normalize(b.centroid() - s.camera.position);
        EXPECT_GT(dot(s.camera.forward, toScene), std::cos(radians(20.0f))) << rel;
    }
}

// SMD materials carry no diffuse colour: Assimp's Get() would write black into the default grey.
TEST(ImportCameras, MissingDiffuseKeepsTheDefaultAlbedo) {
    auto dir = test::scratchDir();
    Scene s = loadScene(test::writeFile(
        dir / "tri.smd",
        "version 1\nnodes\n  0 \"root\" -1\nend\nskeleton\ntime 0\n  0 0 0 0 0 0 0\nend\n"
        "triangles\nnone.tga\n0  0 0 0 0 0 1 0 0\n0  1 0 0 0 0 1 1 0\n0  1 1 0 0 0 1 1 1\nend\n"));
    ASSERT_FALSE(s.materials.empty());
    EXPECT_EQ(s.materials[0].albedo, Material{}.albedo);
}

// A 200 cm triangle, a camera at (0, 50, 500) cm with znear 10, zfar 10000 and yfov 40, and
// optionally a point light at (0, 300, 0) cm, in a file whose unit is the centimetre.
std::string centimetreCollada(bool withLight) {
    std::string light =
        withLight
            ? R"(<library_lights><light id="l"><technique_common><point><color>1 1 1</color></point></technique_common></light></library_lights>)"
            : "";
    std::string lightNode =
        withLight
            ? R"(<node id="ln"><translate>0 300 0</translate><instance_light url="#l"/></node>)"
            : "";
    return R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="0.01" name="centimeter"/><up_axis>Y_UP</up_axis></asset>
<library_cameras><camera id="c" name="c"><optics><technique_common><perspective><yfov>40</yfov><aspect_ratio>1</aspect_ratio><znear>10</znear><zfar>10000</zfar></perspective></technique_common></optics></camera></library_cameras>
)" + light +
           R"(
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="9">-100 0 0 100 0 0 0 100 0</float_array>
<technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s">
<node id="n"><instance_geometry url="#g"/></node>
<node id="cn"><translate>0 50 500</translate><instance_camera url="#c"/></node>
)" + lightNode +
           R"(
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>
)";
}

// <unit meter="0.01">: Assimp scales the geometry; the CGL pass must scale the camera (position
// and clip planes), lights and spheres alike.
TEST(ImportCameras, ColladaUnitScalesCameraAndLights) {
    auto dir = test::scratchDir();
    Scene s = loadAsFile(test::writeFile(dir / "cm.dae", centimetreCollada(true)));
    Bounds3 b = s.storedBounds();
    EXPECT_NEAR(b.hi.x - b.lo.x, 2.0f, 1e-5f);  // geometry: 200 cm
    Vec3d cam = s.world(s.camera.position);
    EXPECT_NEAR(cam.y, 0.5, 1e-6);
    EXPECT_NEAR(cam.z, 5.0, 1e-6);
    EXPECT_NEAR(s.camera.nearClip, 0.1f, 1e-7f);
    EXPECT_NEAR(s.camera.farClip, 100.0f, 1e-4f);
    const Light* point = test::findLight(s, LightKind::Point);
    ASSERT_NE(point, nullptr);
    EXPECT_NEAR(s.world(point->position).y, 3.0, 1e-6);
}

// The same COLLADA read by Assimp alone (.xml): its camera's near clip is in centimetres too.
// (Assimp 5.2 ignores the optics of a COLLADA camera without a name attribute.)
TEST(ImportCameras, AssimpCameraClipPlanesFollowTheNodeScale) {
    auto dir = test::scratchDir();
    Scene s = loadAsFile(test::writeFile(dir / "cm.xml", centimetreCollada(false)));
    ASSERT_TRUE(s.hasFileCamera);
    EXPECT_NEAR(s.camera.nearClip, 0.1f, 1e-6f);
    EXPECT_NEAR(s.world(s.camera.position).z, 5.0, 1e-5);
    EXPECT_NEAR(s.camera.vFovDeg, 40.0f, 1e-3f);
}

// Issue #33 item 3: a COLLADA camera node scaled by 1e3 scales znear and zfar too (10 cm becomes
// 100 m), putting the near plane beyond the triangle 5 m away: the image shows nothing. A warning
// names the camera and the numbers, through the CGL pass (.dae) and Assimp (.xml) alike.
TEST(ImportCameras, AClipRangeThatExcludesTheSceneIsAWarning) {
    auto dir = test::scratchDir();
    std::string plain = centimetreCollada(false), scaled = plain;
    const std::string node = "<translate>0 50 500</translate>";
    scaled.replace(scaled.find(node), node.size(), node + "<scale>1000 1000 1000</scale>");
    for (const char* ext : {".dae", ".xml"}) {
        Scene s = loadAsFile(test::writeFile(dir / (std::string("scaled") + ext), scaled));
        ASSERT_EQ(test::warningsNaming(s, "excludes every object"), 1) << ext;
        // The camera's name (the XML pass: the <camera>'s, Assimp: its node's) and the numbers.
        EXPECT_TRUE(
            test::hasWarning(s, ext == std::string(".dae") ? "camera 'c':" : "camera 'cn':"))
            << ext;
        EXPECT_TRUE(test::hasWarning(s, "its clip range 100 .. 1e+05")) << ext;
        EXPECT_TRUE(test::hasWarning(s, "which lie 5 .. 5 in front of it")) << ext;
        Scene fine = loadAsFile(test::writeFile(dir / (std::string("plain") + ext), plain));
        EXPECT_FALSE(test::hasWarning(fine, "clip range")) << ext;
    }
    // A far plane short of the scene likewise.
    std::string near = plain;
    near.replace(near.find("<zfar>10000</zfar>"), 18, "<zfar>20</zfar>");
    Scene s = loadAsFile(test::writeFile(dir / "short.dae", near));
    EXPECT_TRUE(test::hasWarning(s, "camera 'c': its clip range 0.1 .. 0.2")) << s.warnings[0];
}

// A flat mesh in the x = 0 plane would be seen edge-on by the default (+Z) framing.
TEST(ImportCameras, FlatSceneIsFramedFaceOn) {
    auto dir = test::scratchDir();
    Scene s = loadScene(
        test::writeFile(dir / "wall.obj", "v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0 1\nf 1 2 3 4\n"));
    EXPECT_GT(std::abs(s.camera.forward.x), 0.9f);
}

}  // namespace
}  // namespace kiln
