// CS184 parity of the command line and the display: -o 0|1, -e, -b, -d (-H with -l: see
// test_integrators), --exposure, the CS184 OCIO view against the course's display code,
// --accel brute and --emitters camera.
#include <OpenImageIO/imageio.h>

#include <cmath>

#include "color/image_output.h"
#include "renderer/accel/brute_force.h"
#include "renderer/core/sampler.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

// kiln's exit code for `kiln ARGS` (output discarded).
int kiln(const std::string& args) {
    return std::system((std::string(KILN_BINARY) + " " + args + " >/dev/null 2>&1").c_str()) >> 8;
}

std::vector<float> readPixels(const std::string& path, int& w, int& h) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    if (!in) return {};
    w = in->spec().width, h = in->spec().height;
    std::vector<float> px(size_t(w) * h * 3);
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
    return px;
}

std::vector<float> readPixels(const std::string& path) {
    int w, h;
    return readPixels(path, w, h);
}

// The course program's display of one channel (CGL HDRImageBuffer::toColor and
// ImageBuffer::update_pixel): x sqrt(2^level) with level 1, ^(1/2.2), clamp, truncate to 8 bits.
double courseCode(double radiance, double* fraction = nullptr) {
    double exposure = std::sqrt(std::pow(2.0, 1.0));
    // std::max(0, std::min(NaN, 1)) is 0: a negative value's NaN power displays black.
    double v = std::max(0.0, std::min(std::pow(radiance * exposure, double(1.0f / 2.2f)), 1.0));
    if (fraction) *fraction = v * 255 - std::floor(v * 255);
    return std::floor(v * 255);
}

TEST(Cs184View, PngCodeValuesAreTheCoursesOnKnownRadiance) {
    // A ramp of radiances over the whole range, negative and above white included.
    const int n = 400;
    Film film(n, 1);
    std::vector<double> radiance(n);
    for (int i = 0; i < n; ++i) {
        radiance[size_t(i)] = i == 0 ? -0.25 : 1.2 * std::pow(double(i) / n, 2.5);
        film.add(i, 0, Color(float(radiance[size_t(i)])));
    }
    std::string png = (test::scratchDir() / "cs184.png").string();
    writePreview(png, film, "sRGB", "CS184");
    std::vector<float> px = readPixels(png);
    ASSERT_EQ(px.size(), size_t(n) * 3);
    int exact = 0;
    for (int i = 0; i < n; ++i) {
        double fraction;
        double want = courseCode(radiance[size_t(i)], &fraction);
        double got = std::round(px[size_t(i) * 3] * 255.0);
        // float (OCIO) against double (course) arithmetic may differ at a code boundary only.
        bool nearBoundary = fraction < 1e-3 || fraction > 1 - 1e-3;
        if (nearBoundary)
            EXPECT_NEAR(got, want, 1.0) << "L = " << radiance[size_t(i)];
        else
            EXPECT_EQ(got, want) << "L = " << radiance[size_t(i)];
        exact += got == want;
    }
    EXPECT_GT(exact, n - 5);
    // Known points: 0.5 / sqrt(2) displays as 0.5^(1/2.2) = 0.7297, code 186.08 -> 186 (the view
    // sits half a code lower, so rounding finds the truncated code); 1 / sqrt(2) and above: white.
    EXPECT_EQ(courseCode(0.5 / std::sqrt(2.0)), 186);
    EXPECT_NEAR(displayTransform(float(0.5 / std::sqrt(2.0)), "sRGB", "CS184"),
                std::pow(0.5, 1 / 2.2) - 0.5 / 255, 1e-5);
    EXPECT_NEAR(displayTransform(1.0f, "sRGB", "CS184"), 254.5 / 255, 1e-6);
}

TEST(Cs184View, ExposureScalesTheLightBeforeTheDisplay) {
    Film base(64, 1), doubled(64, 1);
    for (int i = 0; i < 64; ++i) {
        base.add(i, 0, Color(0.01f * float(i)));
        doubled.add(i, 0, Color(0.02f * float(i)));
    }
    auto dir = test::scratchDir();
    writePreview((dir / "a.png").string(), base, "sRGB", "Standard", 1.0f);
    writePreview((dir / "b.png").string(), doubled, "sRGB", "Standard");
    writePreview((dir / "c.png").string(), base, "sRGB", "Standard");
    std::vector<float> a = readPixels((dir / "a.png").string());
    EXPECT_EQ(a, readPixels((dir / "b.png").string()));
    EXPECT_NE(a, readPixels((dir / "c.png").string()));
    // Down as well as up, the preview staying opaque: alpha is coverage, not light (the preview
    // once scaled it too and showed a -1 stop image half transparent).
    writePreview((dir / "d.png").string(), doubled, "sRGB", "Standard", -1.0f);
    EXPECT_EQ(readPixels((dir / "d.png").string()), readPixels((dir / "c.png").string()));
    auto in = OIIO::ImageInput::open((dir / "d.png").string());
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().nchannels, 4);
    std::vector<float> rgba(64 * 4);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, rgba.data()));
    for (int i = 0; i < 64; ++i) EXPECT_EQ(rgba[size_t(i) * 4 + 3], 1.0f) << i;
}

// Brute force finds exactly the reference BVH's hits (same primitive tests, same tie rule) on
// triangles, spheres and instances, and the same occlusion.
TEST(BruteForce, HitsWhatTheReferenceBvhHits) {
    Scene spheres = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    Scene cow = loadScene(test::cs184("meshedit/cow.dae"));
    Scene instanced = test::sceneWith(test::sphereMesh(8, 16));
    for (int i = 0; i < 4; ++i) {
        Mat4 xf;
        xf.m[0][0] = xf.m[1][1] = xf.m[2][2] = 0.5 + 0.1 * i;
        xf.m[0][3] = (i % 2) * 1.5 - 0.75, xf.m[1][3] = (i / 2) * 1.5 - 0.75;
        instanced.instances.push_back(Instance::place(0, xf));
    }
    for (const Scene* s : {&spheres, &cow, &instanced}) {
        auto brute = makeBruteForceAccelerator(*s), bvh = makeReferenceAccelerator(*s);
        Bounds3 box = s->storedBounds();
        Vec3 centre = box.centroid(), extent = box.hi - box.lo;
        int hits = 0;
        for (int i = 0; i < 3000; ++i) {
            Sampler r(7, uint64_t(i), 0);
            Vec3 from = centre + Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, r.next1D() - 0.5f) *
                                     extent * 2.0f;
            Vec3 to = centre +
                      Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, r.next1D() - 0.5f) * extent * 0.8f;
            Ray ray{from, 0, to - from, kInfinity};
            Hit a, b;
            bool ha = brute->intersect(ray, a), hb = bvh->intersect(ray, b);
            ASSERT_EQ(ha, hb) << s->sourcePath << " ray " << i;
            EXPECT_EQ(brute->occluded(ray), ha);
            if (!ha) continue;
            ++hits;
            EXPECT_EQ(a.t, b.t);
            EXPECT_EQ(a.shape, b.shape);
            EXPECT_EQ(a.prim, b.prim);
            EXPECT_EQ(a.instance, b.instance);
        }
        EXPECT_GT(hits, 300) << s->sourcePath;
    }
}

struct MeanAndError {
    double mean = 0, stderror = 0;
};

// Image-mean luminance of a render of s and its standard error (from the per-pixel variances).
MeanAndError renderMean(const Scene& s, const PathOptions& path) {
    auto accel = makeEmbreeAccelerator(s);
    Film film = test::renderJob(s, *accel, test::jobOptions(48, 36, 32, path));
    MeanAndError e;
    double var = 0, pixels = double(film.width()) * film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            double n = film.samples(x, y), s1 = film.luminanceSum(x, y);
            e.mean += s1 / n / pixels;
            var += std::max(0.0, (film.luminanceSquareSum(x, y) - s1 * s1 / n) / (n - 1)) / n;
        }
    e.stderror = std::sqrt(var) / pixels;
    return e;
}

// --emitters camera, the course program on CBempty (an emissive ceiling and a point light): the
// ceiling is no light, so direct lighting is the point light's plus the ceiling seen by the camera.
TEST(Cs184Emitters, CameraOnlyEmittersLightNothing) {
    LoadOptions courseLoad;
    courseLoad.emissiveMeshLights = false;
    Scene course = loadScene(test::cs184("sky/CBempty.dae"), courseLoad);
    Scene kiln = loadScene(test::cs184("sky/CBempty.dae"));
    ASSERT_NE(test::findLight(kiln, LightKind::MeshEmitter), nullptr);
    EXPECT_EQ(test::findLight(course, LightKind::MeshEmitter), nullptr);
    ASSERT_NE(test::findLight(course, LightKind::Point), nullptr);
    Scene dark = kiln;  // no emission at all, the point light alone
    for (Material& m : dark.materials) m.emission = Color(0.0f);
    std::erase_if(dark.lights, [](const Light& l) { return l.kind == LightKind::MeshEmitter; });

    PathOptions direct, courseDirect, emissionOnly;
    direct.maxDepth = courseDirect.maxDepth = 1;
    direct.sampling = courseDirect.sampling = DirectSampling::Light;
    courseDirect.unsampledEmittersLight = false;
    emissionOnly.maxDepth = 0;
    MeanAndError c = renderMean(course, courseDirect), k = renderMean(kiln, direct);
    MeanAndError point = renderMean(dark, direct), seen = renderMean(kiln, emissionOnly);
    double bound = 5 * std::sqrt(c.stderror * c.stderror + point.stderror * point.stderror +
                                 seen.stderror * seen.stderror);
    EXPECT_NEAR(c.mean, point.mean + seen.mean, bound);
    // kiln's ceiling lights the box (docs/cs184.md): more light than 5 standard errors explain.
    EXPECT_GT(k.mean - c.mean, 5 * std::sqrt(k.stderror * k.stderror + c.stderror * c.stderror));
    std::printf("CBempty -m 1: kiln %.4f, course emitters %.4f, ratio %.3f\n", k.mean, c.mean,
                k.mean / c.mean);
}

class Cs184Flags : public ::testing::Test {
  protected:
    std::string scene = test::cs184("sky/CBspheres_lambertian.dae");
    std::filesystem::path dir = test::scratchDir();
    // A tiny deterministic render of the scene with these flags, into dir/NAME.
    int render(const std::string& flags, const std::string& name) {
        return kiln("render " + scene + " -r 24 18 -s 4 -t 2 -q " + flags + " --output " +
                    (dir / name).string());
    }
    std::vector<float> exr(const std::string& name) {
        return readPixels((dir / (name + ".exr")).string());
    }
};

TEST_F(Cs184Flags, OZeroIsAccumulateOffNotAnOutputName) {
    ASSERT_EQ(kiln("render " + scene + " -r 24 18 -s 4 -t 2 -q -m 3 -o 0 -f " +
                   (dir / "off.png").string()),
              0);
    EXPECT_FALSE(std::filesystem::exists(dir / "0.exr"));
    EXPECT_FALSE(std::filesystem::exists("0.exr"));
    ASSERT_EQ(render("-m 3 --bounce-only", "bounceonly"), 0);
    ASSERT_EQ(render("-m 3", "all"), 0);
    ASSERT_EQ(render("-m 3 -o 0 -o 1", "on"), 0);
    EXPECT_EQ(exr("off"), exr("bounceonly"));
    EXPECT_EQ(exr("on"), exr("all"));
    EXPECT_NE(exr("off"), exr("all"));
    // Any other -o value is still the output base name; --output names a file "0".
    ASSERT_EQ(kiln("render " + scene + " -r 8 6 -q -o " + (dir / "named").string()), 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "named.exr"));
    ASSERT_EQ(render("", "0"), 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "0.exr"));
}

TEST_F(Cs184Flags, CourseShortFlagsMeanTheLongOnes) {
    std::string env = test::shared("envmaps/studio.exr");
    ASSERT_EQ(render("-e " + env, "e"), 0);
    ASSERT_EQ(render("--env " + env, "env"), 0);
    EXPECT_EQ(exr("e"), exr("env"));
    ASSERT_EQ(render("-b 0.05 -d 3", "bd"), 0);
    ASSERT_EQ(render("--aperture 0.05 --focus 3", "lens"), 0);
    ASSERT_EQ(render("", "pinhole"), 0);
    EXPECT_EQ(exr("bd"), exr("lens"));
    EXPECT_NE(exr("bd"), exr("pinhole"));
    EXPECT_EQ(render("--exposure nan", "bad"), 2);
    // Brute force renders small jobs exactly as the BVH does, and refuses one of hours at once.
    ASSERT_EQ(render("--accel brute", "brute"), 0);
    ASSERT_EQ(render("--accel reference", "bvh"), 0);
    EXPECT_EQ(exr("brute"), exr("bvh"));
    EXPECT_EQ(kiln("render " + test::cs184("meshedit/cow.dae") +
                   " -r 1920 1080 -s 256 -q --accel brute --output " + (dir / "slow").string()),
              2);
    EXPECT_FALSE(std::filesystem::exists(dir / "slow.exr"));
    EXPECT_EQ(render("--view NoSuchView", "bad"), 2);
}

}  // namespace
}  // namespace kiln
