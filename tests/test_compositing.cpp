// Compositor-grade EXRs: alpha as coverage, Z from one sample, camera matrices, Cryptomatte, layer
// names, every compression, numbers as numbers.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "color/image_output.h"
#include "integrators/crypto_names.h"
#include "kiln_run.h"
#include "renderer/exr_scene.h"
#include "renderer/film/cryptomatte.h"
#include "renderer/render_job.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr int kW = 48, kH = 36, kSpp = 64;

// One tilted triangle in front of a pinhole camera on the z axis, nothing behind it.
Scene triangleScene() {
    TriangleMesh m;
    m.name = "tri";
    m.positions = {-1.5f, -1.0f, -0.5f, 1.7f, -0.8f, 0.3f, 0.2f, 1.4f, 0.0f};
    m.indices = {0, 1, 2};
    m.materialIds = {0};
    m.finalizePadding();
    Scene s = test::sceneWith(std::move(m));
    s.camera.position = {0, 0, 5};
    s.camera.forward = {0, 0, -1};
    s.camera.up = {0, 1, 0};
    s.camera.hFovDeg = 50, s.camera.vFovDeg = 38;
    s.hasFileCamera = true;
    return s;
}

RenderJobOptions normalsJob(const AovRequest& aovs) {
    RenderJobOptions o = test::jobOptions(kW, kH, kSpp, {}, aovs);
    o.integrator = IntegratorKind::Normals;
    return o;
}

using P2 = std::array<double, 2>;

// Row-vector point times a 4x4 matrix, divided by w.
std::array<double, 3> transform(const std::array<float, 16>& m, const Vec3& p) {
    double v[4];
    for (int c = 0; c < 4; ++c) v[c] = p.x * m[c] + p.y * m[4 + c] + p.z * m[8 + c] + m[12 + c];
    return {v[0] / v[3], v[1] / v[3], v[2] / v[3]};
}

// Area of the unit pixel square at (x, y) inside the convex polygon (Sutherland-Hodgman).
double coveredArea(std::vector<P2> poly, int x, int y) {
    auto clip = [&](int axis, double bound, bool keepAbove) {
        std::vector<P2> out;
        for (size_t i = 0; i < poly.size(); ++i) {
            P2 a = poly[i], b = poly[(i + 1) % poly.size()];
            bool ina = keepAbove ? a[axis] >= bound : a[axis] <= bound;
            bool inb = keepAbove ? b[axis] >= bound : b[axis] <= bound;
            if (ina) out.push_back(a);
            if (ina != inb) {
                double t = (bound - a[axis]) / (b[axis] - a[axis]);
                out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
            }
        }
        poly = out;
    };
    clip(0, x, true), clip(0, x + 1, false), clip(1, y, true), clip(1, y + 1, false);
    double area = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const P2 &a = poly[i], &b = poly[(i + 1) % poly.size()];
        area += a[0] * b[1] - a[1] * b[0];
    }
    return std::abs(area) / 2;
}

TEST(Compositing, AlphaIsCoverageAtTheSilhouetteAndBeautyIsPremultiplied) {
    Scene s = triangleScene();
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = normalsJob(AovRequest::parse("Z", 1));
    Film f = test::renderJob(s, *accel, o);
    // The triangle's exact footprint in raster space, through the EXR's worldToNDC.
    ExrCamera cam = exrCamera(s, o.settings);
    std::vector<P2> footprint;
    for (int v = 0; v < 3; ++v) {
        auto ndc = transform(cam.worldToNDC, s.meshes[0].vertex(uint32_t(v)));
        footprint.push_back({ndc[0] * kW, ndc[1] * kH});
    }
    Color inside = f.pixel(kW / 2, kH / 2);  // the normals integrator's constant colour
    ASSERT_EQ(f.alpha(kW / 2, kH / 2), 1.0f);
    int silhouette = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            double area = coveredArea(footprint, x, y), a = f.alpha(x, y);
            // Each sample covers with probability `area`: binomial, 5 sigma (+ one sample).
            double tol = 5 * std::sqrt(area * (1 - area) / kSpp) + 1.0 / kSpp;
            EXPECT_NEAR(a, area, tol) << x << " " << y;
            if (area == 0 || area == 1) {
                EXPECT_EQ(a, area) << x << " " << y;
            }
            silhouette += a > 0 && a < 1;
            // Premultiplied: colour = alpha x the surface's colour, to float rounding.
            EXPECT_NEAR(f.pixel(x, y).x, a * inside.x, 1e-5) << x << " " << y;
        }
    EXPECT_GT(silhouette, 20);
}

TEST(Compositing, DepthIsTheNearestSampleNeverAMeanWithMisses) {
    Scene s = triangleScene();
    auto accel = makeEmbreeAccelerator(s);
    for (DepthMode mode : {DepthMode::Ray, DepthMode::CameraZ}) {
        AovRequest aovs = AovRequest::parse("Z,P", 1);
        aovs.depth = mode;
        RenderJobOptions o = normalsJob(aovs);
        Film f = test::renderJob(s, *accel, o);
        ExrCamera cam = exrCamera(s, o.settings);
        // Z of a point of the triangle lies between its vertices' (both are convex in the point
        // for the ray distance, linear for camera z).
        auto zOf = [&](const Vec3& p) {
            return mode == DepthMode::CameraZ ? transform(cam.worldToCamera, p)[2]
                                              : double(length(p - s.camera.position));
        };
        double lo = 1e30, hi = 0;
        for (int v = 0; v < 3; ++v) {
            double z = zOf(s.meshes[0].vertex(uint32_t(v)));
            lo = std::min(lo, z), hi = std::max(hi, z);
        }
        if (mode == DepthMode::Ray) lo = 0;  // the nearest point may be inside the triangle
        int silhouette = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                float a = f.alpha(x, y), z = f.depth(x, y);
                if (a == 0) {
                    EXPECT_EQ(z, kInfinity) << x << " " << y;
                    continue;
                }
                silhouette += a < 1;
                EXPECT_GE(z, lo - 1e-4) << x << " " << y;
                EXPECT_LE(z, hi + 1e-4) << x << " " << y;
                if (a < 1 || mode == DepthMode::Ray) continue;
                // Inside, camera z against the pixel's mean position: within the plane's z
                // change across one pixel (the sample is one of the pixel's).
                size_t px = 0;
                while (f.layout().channels()[px].name != "P.X") ++px;
                Vec3 p(f.aov(x, y, px), f.aov(x, y, px + 1), f.aov(x, y, px + 2));
                EXPECT_NEAR(z, zOf(p), 0.02) << x << " " << y;
            }
        EXPECT_GT(silhouette, 20);
    }
}

TEST(Compositing, TransparentBackgroundDropsEscapedLightAndEmittersDoNotCover) {
    for (bool transparent : {false, true}) {
        AovRequest aovs = AovRequest::parse("emission", 1);
        aovs.transparent = transparent;
        Film f(3, 1, aovs);
        SampleRecord background, emitter, surface;
        background.L = background.emission = Color(0.25f);  // environment seen directly
        emitter.L = emitter.emission = Color(4.0f);
        emitter.hit = emitter.hitEmitter = true;
        surface.L = surface.emission = Color(0.5f);
        surface.hit = true;
        for (int k = 0; k < 4; ++k) f.add(0, 0, background), f.add(1, 0, emitter);
        for (int k = 0; k < 4; ++k) f.add(2, 0, k % 2 ? surface : background);
        EXPECT_EQ(f.alpha(0, 0), 0.0f);
        EXPECT_EQ(f.pixel(0, 0).x, transparent ? 0.0f : 0.25f);
        EXPECT_EQ(f.aov(0, 0, 0), transparent ? 0.0f : 0.25f);
        EXPECT_EQ(f.alpha(1, 0), transparent ? 0.0f : 1.0f);
        EXPECT_EQ(f.pixel(1, 0).x, 4.0f);  // an emitter's light stays (additive)
        EXPECT_EQ(f.alpha(2, 0), 0.5f);
        EXPECT_FLOAT_EQ(f.pixel(2, 0).x, transparent ? 0.25f : 0.375f);
    }
}

// The scene's object names by the objectid AOV's numbering (meshes, then spheres).
std::string objectName(const Scene& s, const CryptoNames& names, float objectId) {
    size_t id = size_t(objectId);
    return id < s.meshes.size() ? names.meshes[id] : names.spheres[id - s.meshes.size()];
}

TEST(Compositing, CryptomatteMatteDecodesToTheObjectsCoverage) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = test::jobOptions(32, 24, 16, {}, AovRequest::parse("crypto_object", 1));
    o.path.maxDepth = 1;
    RenderJob job(s, *accel, o);
    Film f = job.makeFilm();
    job.render(f);
    ExrOptions exr;
    addSceneToExr(exr, s, o.settings, o.aovs);
    std::string path = (test::scratchDir() / "crypto.exr").string();
    writeExr(path, f, {}, exr);

    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    std::string key = "cryptomatte/" + cryptoLayerKey("CryptoObject") + "/";
    EXPECT_EQ(spec.get_string_attribute(key + "name"), "CryptoObject");
    EXPECT_EQ(spec.get_string_attribute(key + "hash"), "MurmurHash3_32");
    EXPECT_EQ(spec.get_string_attribute(key + "conversion"), "uint32_to_float32");
    auto manifest = nlohmann::json::parse(spec.get_string_attribute(key + "manifest"));
    CryptoNames names(s);
    ASSERT_FALSE(names.spheres.empty());
    const std::string target = names.spheres[0];
    ASSERT_TRUE(manifest.contains(target));
    // The matte's id, from the manifest's hex (as a compositor decodes it).
    uint32_t bits = uint32_t(std::stoul(manifest[target].get<std::string>(), nullptr, 16));
    float id = cryptoIdFloat(bits);

    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    int first = spec.channelindex("CryptoObject00.R");
    ASSERT_GE(first, 0);
    ASSERT_EQ(spec.channelindex("CryptoObject02.A"), first + 11);
    int covered = 0;
    for (int y = 0; y < spec.height; ++y)
        for (int x = 0; x < spec.width; ++x) {
            const float* p = &px[(size_t(y) * spec.width + x) * spec.nchannels + first];
            float matte = 0;
            for (int r = 0; r < kCryptoRanks; ++r)
                if (p[2 * r] == id) matte += p[2 * r + 1];
            // The object's pixels: its samples replayed one by one.
            int hits = 0;
            for (int k = 0; k < o.settings.spp; ++k) {
                RayCounter rays;
                SampleRecord r = job.traceSample(x, y, k, rays);
                hits += r.hit && objectName(s, names, r.objectId) == target;
            }
            EXPECT_FLOAT_EQ(matte, float(hits) / float(o.settings.spp)) << x << " " << y;
            covered += hits > 0;
        }
    EXPECT_GT(covered, 10);
}

TEST(Compositing, EveryAovHasALayerAndCameraMetadataAndNumbersAreNumbers) {
    Scene s = triangleScene();
    auto accel = makeEmbreeAccelerator(s);
    RenderJobOptions o = normalsJob(AovRequest::parse("all", 2));
    o.settings.spp = 2;
    RenderJob job(s, *accel, o);
    Film f = job.makeFilm();
    RenderStats stats = job.render(f);
    ExrOptions exr;
    addSceneToExr(exr, s, o.settings, o.aovs);
    for (const auto& [value, compression] : EnumNames<ExrCompression>::table) {
        exr.compression = value;
        std::string path = (test::scratchDir() / (std::string("layers_") + compression + ".exr")).string();
        writeExr(path, f, job.metadata(stats, f), exr);
        auto in = OIIO::ImageInput::open(path);
        ASSERT_TRUE(in) << compression;
        const OIIO::ImageSpec& spec = in->spec();
        EXPECT_EQ(spec.get_string_attribute("compression"), compression);
        // Blender's multilayer reader keeps "layer.channel" (and the standard R G B A Z).
        for (const std::string& name : spec.channelnames)
            EXPECT_TRUE(name.find('.') != std::string::npos || name.size() == 1) << name;
        for (const char* c :
             {"samples.X", "variance.V", "primid.X", "objectid.X", "Z", "CryptoMaterial00.R"})
            EXPECT_GE(spec.channelindex(c), 0) << c;
        EXPECT_EQ(spec.z_channel, spec.channelindex("Z"));
        const OIIO::ParamValue* w2c = spec.find_attribute("worldToCamera", OIIO::TypeMatrix);
        ASSERT_NE(w2c, nullptr);
        ASSERT_NE(spec.find_attribute("worldToNDC", OIIO::TypeMatrix), nullptr);
        EXPECT_EQ(spec.getattributetype("kiln:spp"), OIIO::TypeInt);
        EXPECT_EQ(spec.getattributetype("kiln:render_seconds"), OIIO::TypeDesc::DOUBLE);
        EXPECT_EQ(spec.getattributetype("kiln:integrator"), OIIO::TypeString);
        EXPECT_GE(spec.get_int_attribute("kiln:threads"), 1);
        EXPECT_EQ(spec.get_string_attribute("kiln:depth"), "distance along the camera ray");
    }
    // The camera sits at (0, 0, 5) looking down -z: the origin is 5 in front of it.
    auto c = transform(exr.camera->worldToCamera, Vec3(0.0f));
    EXPECT_NEAR(c[0], 0, 1e-6);
    EXPECT_NEAR(c[1], 0, 1e-6);
    EXPECT_NEAR(c[2], 5, 1e-6);
}

TEST(Compositing, CommandLineOptionsReachTheFile) {
    auto dir = test::scratchDir();
    test::CliRun r = test::runKiln("render " + test::cs184("sky/CBspheres.dae") +
                                   " -r 24 18 -s 2 -q --transparent --depth camera --compression "
                                   "dwab --aov Z,crypto_material -o " +
                                   (dir / "o").string());
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open((dir / "o.exr").string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.get_string_attribute("compression"), "dwab");
    EXPECT_EQ(spec.get_string_attribute("kiln:depth"), "camera-space z (along the view axis)");
    EXPECT_NE(spec.get_string_attribute("kiln:alpha").find("transparent"), std::string::npos);
    EXPECT_GE(spec.channelindex("CryptoMaterial00.R"), 0);
    EXPECT_NE(spec.find_attribute("worldToNDC", OIIO::TypeMatrix), nullptr);
    EXPECT_NE(spec.get_string_attribute("Software").find("commit"), std::string::npos);
    test::CliRun bad = test::runKiln("render " + test::cs184("sky/CBspheres.dae") +
                                     " -q --compression lzma -o " + (dir / "b").string());
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("dwab"), std::string::npos) << bad.err;  // names the choices
}

}  // namespace
}  // namespace kiln
