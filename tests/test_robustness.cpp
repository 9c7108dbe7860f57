// Hard cases stay numerically stable: watertightness, far-away and rescaled scenes, bent shading
// normals, degenerate geometry, deep paths, and non-finite samples that never reach the image.
#include <algorithm>
#include <cstdio>

#include "integrators/lights.h"
#include "integrators/path.h"
#include "renderer/core/sampler.h"
#include "renderer/geometry/interaction.h"
#include "renderer/render_loop.h"
#include "renderer/validation/crosscheck.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

struct Estimate {
    double mean = 0, se = 0;
};

// Mean and standard error of a block of pixels' luminance means.
Estimate blockEstimate(const Film& f, int x0, int y0, int x1, int y1) {
    Estimate e;
    double var = 0;
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x, ++n) {
            double c = f.samples(x, y);
            e.mean += f.luminanceSum(x, y) / c;
            var += f.luminanceVariance(x, y);
        }
    e.mean /= n;
    e.se = std::sqrt(var) / n;
    return e;
}

Film renderScene(const Scene& s, int w, int h, int spp, PathOptions opt = {},
                 AcceleratorKind kind = AcceleratorKind::Embree) {
    auto accel =
        kind == AcceleratorKind::Embree ? makeEmbreeAccelerator(s) : makeReferenceAccelerator(s);
    return test::renderJob(s, *accel, test::jobOptions(w, h, spp, opt));
}

// --- Watertightness
// --------------------------------------------------------------------------------

// Rays aimed exactly at interior edges (shared by two triangles) and vertices, from the front of
// both neighbours (within 60 degrees of each normal). A leak is a ray that finds nothing up to its
// target (t = 1): it passed through.
struct LeakCount {
    uint64_t rays = 0, embree = 0, reference = 0, watertight = 0;
    uint64_t vertexRays = 0,
             embreeAtVertices = 0;  // Embree's share at exact vertices (see docs/robustness.md)
};

LeakCount edgeLeaks(const Scene& s, uint64_t seed) {
    auto embree = makeEmbreeAccelerator(s);
    EmbreeOptions watertightOptions;
    watertightOptions.watertight = true;
    auto watertight = makeEmbreeAccelerator(s, watertightOptions);
    auto reference = makeReferenceAccelerator(s);
    // The target is at t = 1 up to the rounding of origin + direction (a few ulps of the
    // coordinates, over the ray's length).
    auto leaks = [](const Accelerator& accel, const Ray& ray) {
        float scale = std::max(
            {std::abs(ray.origin.x), std::abs(ray.origin.y), std::abs(ray.origin.z), 1e-30f});
        float slack = 16 * scale * 0x1p-24f / length(ray.dir) + 1e-5f;
        Hit h;
        return !accel.intersect(ray, h) || h.t > 1 + slack;
    };
    LeakCount out;
    for (const TriangleMesh& m : s.meshes) {
        std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
        std::vector<std::vector<uint32_t>> fan(m.vertexCount());
        for (uint32_t t = 0; t < m.triangleCount(); ++t)
            for (int e = 0; e < 3; ++e) {
                uint32_t a = m.indices[3 * t + e], b = m.indices[3 * t + (e + 1) % 3];
                edges[{std::min(a, b), std::max(a, b)}].push_back(t);
                fan[a].push_back(t);
            }
        auto normal = [&](uint32_t t) {
            Vec3 p0 = m.vertex(m.indices[3 * t]), p1 = m.vertex(m.indices[3 * t + 1]),
                 p2 = m.vertex(m.indices[3 * t + 2]);
            Vec3 n = cross(p1 - p0, p2 - p0);
            return dot(n, n) > 0 ? normalize(n) : Vec3(0.0f);
        };
        // A vertex is closed when every edge around it has two triangles: only then does its fan
        // cover every direction in front of it (a vertex on a hole's rim has a real gap beside it).
        std::vector<bool> closed(m.vertexCount(), true);
        for (const auto& [edge, tris] : edges)
            if (tris.size() != 2) closed[edge.first] = closed[edge.second] = false;
        uint64_t k = 0;
        for (const auto& [edge, tris] : edges) {
            if (tris.size() != 2)
                continue;  // boundary or non-manifold: nothing to be watertight about
            Vec3 n1 = normal(tris[0]), n2 = normal(tris[1]);
            if (dot(n1, n2) < 0.2f) continue;  // too sharp for a direction in front of both
            Vec3 a = m.vertex(edge.first), b = m.vertex(edge.second);
            for (float f : {0.0f, 0.3f, 0.5f}) {
                Vec3 target = a + (b - a) * f;
                for (int j = 0; j < 3; ++j) {
                    Sampler r(seed, k++, 0);
                    Vec3 jitter =
                        Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, r.next1D() - 0.5f) * 1.2f;
                    Vec3 away = normalize(normalize(n1 + n2) + jitter);
                    if (dot(away, n1) < 0.5f || dot(away, n2) < 0.5f) continue;
                    // Aimed at a vertex, the ray passes every triangle of its fan: it must face
                    // them all, or the fan folds in projection and leaves a real gap beside the
                    // vertex.
                    if (f == 0.0f && !closed[edge.first]) continue;
                    if (f == 0.0f &&
                        std::any_of(fan[edge.first].begin(), fan[edge.first].end(),
                                    [&](uint32_t t) { return dot(away, normal(t)) < 0.2f; }))
                        continue;
                    // The winding may face inwards: approach from the side the normals point to
                    // either way.
                    float dist = (0.05f + r.next1D()) * length(b - a) * 20;
                    Ray ray{target + away * dist, 0, -away * dist, kInfinity};
                    ++out.rays;
                    bool embreeMiss = leaks(*embree, ray);
                    if (f == 0.0f) {
                        ++out.vertexRays;
                        out.embreeAtVertices += embreeMiss;
                    } else {
                        out.embree += embreeMiss;
                    }
                    out.reference += leaks(*reference, ray);
                    out.watertight += leaks(*watertight, ray);
                }
            }
        }
    }
    return out;
}

TEST(Watertightness, NoLeaksThroughSharedEdgesOverAMillionRays) {
    LeakCount total;
    auto accumulate = [&](const Scene& s, uint64_t seed, const std::string& what) {
        LeakCount c = edgeLeaks(s, seed);
        EXPECT_EQ(c.embree, 0u) << what << ": Embree leaked through an edge";
        EXPECT_EQ(c.reference, 0u) << what;
        EXPECT_EQ(c.watertight, 0u) << what << ": Embree --watertight leaked";
        EXPECT_GT(c.rays, 1000u) << what;
        // Embree (ROBUST) is watertight along edges but not exactly at vertices: bounded,
        // documented.
        EXPECT_LE(c.embreeAtVertices, c.vertexRays / 200)
            << what << ": " << c.embreeAtVertices << " of " << c.vertexRays;
        total.rays += c.rays;
        total.vertexRays += c.vertexRays;
        total.embreeAtVertices += c.embreeAtVertices;
    };
    accumulate(test::sceneWith(test::sphereMesh(90, 180)), 1, "tessellated sphere");
    accumulate(loadScene(test::shared("meshes/stanford-bunny.obj")), 2, "stanford bunny");
    accumulate(loadScene(test::cs184("meshedit/cow.dae")), 3, "cow");
    accumulate(loadScene(test::cs184("sky/bunny.dae")), 4, "CS184 bunny");
    EXPECT_GE(total.rays, 1000000u);
    std::printf("watertightness: %llu rays, Embree missed %llu of %llu aimed exactly at vertices\n",
                (unsigned long long)total.rays, (unsigned long long)total.embreeAtVertices,
                (unsigned long long)total.vertexRays);
}

TEST(Watertightness, FarFromTheOriginToo) {
    // Embree's verify places its watertightness meshes at (148376, 1234, -223423); so do we,
    // without recentring, to test the traversal itself at that magnitude.
    TriangleMesh ball = test::sphereMesh(40, 80);
    for (size_t v = 0; v < ball.vertexCount(); ++v) {
        ball.positions[3 * v] = ball.positions[3 * v] * 1000 + 148376;
        ball.positions[3 * v + 1] = ball.positions[3 * v + 1] * 1000 + 1234;
        ball.positions[3 * v + 2] = ball.positions[3 * v + 2] * 1000 - 223423;
    }
    LeakCount c = edgeLeaks(test::sceneWith(ball), 9);
    EXPECT_GT(c.rays, 50000u);
    EXPECT_EQ(c.embree, 0u);
    EXPECT_EQ(c.reference, 0u);
    EXPECT_EQ(c.watertight, 0u);
    EXPECT_LE(c.embreeAtVertices, c.vertexRays / 200);
}

TEST(ShadowRays, StopShortOfTheLightByItsErrorBoundAndNeverSelfOcclude) {
    for (float shift : {0.0f, 1e3f, 1e5f}) {
        // A floor and an emissive panel facing it, nothing in between; no recentring (built here).
        TriangleMesh floor = test::gridMesh(8, 8, 0.25f), panel = test::gridMesh(2, 2, 0.25f);
        for (size_t v = 0; v < floor.vertexCount(); ++v) floor.positions[3 * v] += shift;
        for (size_t v = 0; v < panel.vertexCount(); ++v) {
            panel.positions[3 * v] += 0.75f + shift;
            panel.positions[3 * v + 1] += 0.75f;
            panel.positions[3 * v + 2] = 1.0f;
        }
        Scene s = test::sceneWith(floor);
        panel.materialIds = {1};
        s.meshes.push_back(panel);
        Material light;
        light.kind = MaterialKind::Emission;
        light.emission = Color(5.0f);
        s.materials.push_back(light);
        addEmissiveMeshLights(s);
        LightSet lights(s);
        EmbreeOptions watertight;
        watertight.watertight = true;
        for (int mode : {0, 1, 2}) {  // Embree, Embree --watertight, reference
            auto accel = mode == 0   ? makeEmbreeAccelerator(s)
                         : mode == 1 ? makeEmbreeAccelerator(s, watertight)
                                     : makeReferenceAccelerator(s);
            int occluded = 0, tested = 0;
            for (int i = 0; i < 20000; ++i) {
                Sampler r(8, uint64_t(i), 0);
                Ray down{Vec3(shift + r.next1D() * 2, r.next1D() * 2, 0.5f), 0, Vec3(0, 0, -1),
                         kInfinity};
                Hit hit;
                if (!accel->intersect(down, hit) || hit.shape != 0) continue;
                SurfaceInteraction si = makeInteraction(s, down, hit);
                LightSample ls;
                if (!lights.sample(0, si.p, r.next1D(), r.next1D(), ls)) continue;
                ++tested;
                occluded += accel->occluded(spawnRayTo(si, ls.p, ls.pError));
            }
            EXPECT_GT(tested, 10000);
            EXPECT_EQ(occluded, 0) << "shift " << shift << " " << accel->stats().description;
        }
    }
}

// --- Far away and rescaled
// -------------------------------------------------------------------------

// A closed box (2 x 1.5 x 2) with a block inside and an emissive ceiling panel, as OBJ + MTL with
// every coordinate a multiple of 1/16, so translating it by up to 1e6 is exact in float.
std::string writeBoxObj(const std::filesystem::path& dir, const std::string& name, double scale,
                        Vec3d shift) {
    auto P = [&](double x, double y, double z) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", x * scale + shift.x,
                      y * scale + shift.y, z * scale + shift.z);
        return std::string(buf);
    };
    std::string obj = "mtllib " + name + ".mtl\n";
    // Box corners 1..8, block corners 9..16, light 17..20.
    for (double y : {0.0, 1.5})
        for (double z : {-1.0, 1.0})
            for (double x : {-1.0, 1.0}) obj += P(x, y, z);
    for (double y : {0.0, 0.625})
        for (double z : {-0.5, 0.0})
            for (double x : {-0.5, 0.0}) obj += P(x, y, z);
    for (double z : {-0.25, 0.25})
        for (double x : {-0.25, 0.25}) obj += P(x, 1.4375, z);
    auto quads = [&](int base, const char* material) {
        // Faces of a box whose corners are base+0..7 (x fastest, then z, then y).
        int q[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
        std::string f = std::string("usemtl ") + material + "\n";
        for (auto& face : q)
            f += "f " + std::to_string(base + face[0]) + " " + std::to_string(base + face[1]) +
                 " " + std::to_string(base + face[2]) + " " + std::to_string(base + face[3]) + "\n";
        return f;
    };
    obj += "o box\n" + quads(1, "white") + "o block\n" + quads(9, "grey");
    obj += "o light\nusemtl light\nf 17 19 20 18\n";
    test::writeFile(dir / (name + ".mtl"),
                    "newmtl white\nKd 0.7 0.7 0.7\nnewmtl grey\nKd 0.4 0.5 0.6\n"
                    "newmtl light\nKd 0 0 0\nKe 12 12 12\n");
    return test::writeFile(dir / (name + ".obj"), obj);
}

TEST(FarAndScaled, SameImageWhenTranslatedOrScaled) {
    auto dir = test::scratchDir();
    auto render = [&](double scale, Vec3d shift, const std::string& name) {
        Scene s = loadScene(writeBoxObj(dir, name, scale, shift));
        // Inside the box, looking at the block: the camera scales and moves with the scene.
        s.camera.position =
            Vec3(Vec3d(0.75 * scale, 0.75 * scale, 0.875 * scale) + shift - s.origin);
        s.camera.forward = normalize(Vec3(-0.5f, -0.3f, -1));
        s.camera.hFovDeg = s.camera.vFovDeg = 70;
        s.camera.nearClip = float(1e-4 * scale);
        return renderScene(s, 24, 18, 64);
    };
    Film reference = render(1, Vec3d(0.0), "original");
    struct Case {
        double scale;
        Vec3d shift;
        const char* name;
    };
    for (const Case& c :
         {Case{1, Vec3d(1e3, -1e3, 1e3), "moved_1e3"}, Case{1, Vec3d(-1e5, 1e5, 1e5), "moved_1e5"},
          Case{1, Vec3d(1e6, 1e6, -1e6), "moved_1e6"}, Case{1e-3, Vec3d(0.0), "scaled_1e-3"},
          Case{1e3, Vec3d(0.0), "scaled_1e3"}}) {
        Film f = render(c.scale, c.shift, c.name);
        int mismatched = 0, blocks = 0;
        for (int by = 0; by < 18; by += 6)
            for (int bx = 0; bx < 24; bx += 6) {
                Estimate a = blockEstimate(reference, bx, by, bx + 6, by + 6),
                         b = blockEstimate(f, bx, by, bx + 6, by + 6);
                ++blocks;
                mismatched +=
                    std::abs(a.mean - b.mean) > 5 * std::sqrt(a.se * a.se + b.se * b.se) + 1e-6;
            }
        EXPECT_EQ(mismatched, 0) << c.name << " (" << blocks << " blocks)";
        // No acne, no holes: nothing in the closed, lit box renders black.
        for (int y = 0; y < 18; ++y)
            for (int x = 0; x < 24; ++x)
                ASSERT_GT(f.pixel(x, y).x, 0.0f) << c.name << " " << x << "," << y;
    }
}

// --- Bent shading normals and thin walls
// -----------------------------------------------------------

Scene thinWallScene(float bendDegrees) {
    // A one-sided-looking wall (a single quad) at z = 0, a light behind it, the camera in front of
    // it.
    TriangleMesh wall = test::gridMesh(4, 4, 0.5f);
    for (size_t v = 0; v < wall.vertexCount(); ++v)
        wall.positions[3 * v] -= 1, wall.positions[3 * v + 1] -= 1;
    float b = radians(bendDegrees);
    for (size_t v = 0; v < wall.vertexCount(); ++v)  // shading normals leaning hard, alternately
        wall.normals.insert(wall.normals.end(),
                            {std::sin(b) * (v % 2 ? 1.0f : -1.0f), 0.0f, std::cos(b)});
    Scene s = test::sceneWith(wall);
    Light light;
    light.kind = LightKind::Point;
    light.position = Vec3(0, 0, -1);
    light.radiance = Color(50.0f);
    s.lights.push_back(light);
    Light sun;
    sun.kind = LightKind::Directional;
    sun.direction = normalize(Vec3(0.3f, 0.2f, 1.0f));  // travels towards +z: lights the back only
    sun.radiance = Color(3.0f);
    s.lights.push_back(sun);
    s.camera.position = Vec3(0, 0, 3);
    s.camera.hFovDeg = s.camera.vFovDeg = 30;
    return s;
}

TEST(ShadingNormals, NoLightLeaksThroughAThinWallWhateverTheBend) {
    for (float bend : {0.0f, 45.0f, 80.0f, 89.0f}) {
        Scene s = thinWallScene(bend);
        Film f = renderScene(s, 16, 16, 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                ASSERT_EQ(f.pixel(x, y), Color(0.0f)) << "bend " << bend << " at " << x << "," << y;
    }
}

TEST(ShadingNormals, NoBlackSpotsOnALitFloorWithBentNormals) {
    TriangleMesh floor = test::gridMesh(8, 8, 0.25f);
    // The grid lies in z = 0 facing +z; lean its shading normals by up to 75 degrees.
    for (size_t v = 0; v < floor.vertexCount(); ++v) {
        float a = radians(75.0f) * (float((v * 7) % 5) / 4.0f), phi = float(v) * 2.1f;
        floor.normals.insert(floor.normals.end(), {std::sin(a) * std::cos(phi),
                                                   std::sin(a) * std::sin(phi), std::cos(a)});
    }
    Scene s = test::sceneWith(floor);
    Light env;
    env.kind = LightKind::Environment;
    env.radiance = Color(1.0f);
    s.lights.push_back(env);
    s.camera.position = Vec3(1, -1.5f, 1.2f);
    s.camera.forward = normalize(Vec3(0, 1.5f, -1.2f));
    s.camera.hFovDeg = s.camera.vFovDeg = 40;
    Film f = renderScene(s, 20, 20, 16);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x) ASSERT_GT(luminance(f.pixel(x, y)), 0.0f) << x << "," << y;
}

// --- Degenerate geometry
// ---------------------------------------------------------------------------

TEST(Degenerate, ZeroAreaSliverAndParallelCasesStayFinite) {
    TriangleMesh m;
    m.positions = {0, 0, 0, 1,  0, 0, 0, 1,         0,   // regular
                   2, 0, 0, 3,  0, 0, 4, 0,         0,   // zero area (collinear)
                   5, 5, 5, 5,  5, 5, 5, 5,         5,   // zero area (a point)
                   0, 3, 0, 10, 3, 0, 0, 3.000001f, 0};  // sliver
    m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    m.materialIds = {0};
    m.finalizePadding();
    Scene s = test::sceneWith(m);
    auto embree = makeEmbreeAccelerator(s);
    auto reference = makeReferenceAccelerator(s);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        Sampler r(4, uint64_t(i), 0);
        // Rays grazing and parallel to the z = 0 plane, and rays straight at the degenerate ones.
        Vec3 o(r.next1D() * 12 - 1, r.next1D() * 8 - 1, i % 2 ? 0.0f : r.next1D() - 0.5f);
        Vec3 d = i % 2 ? Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, 0)
                       : Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, -o.z);
        Ray ray{o, 0, d, kInfinity};
        for (const Accelerator* a : {embree.get(), reference.get()}) {
            Hit h;
            if (!a->intersect(ray, h)) continue;
            ++hits;
            ASSERT_TRUE(std::isfinite(h.t) && std::isfinite(h.u) && std::isfinite(h.v));
            SurfaceInteraction si = makeInteraction(s, ray, h);
            ASSERT_TRUE(isFinite(si.p) && isFinite(si.ng) && isFinite(si.ns) &&
                        isFinite(si.pError));
            Ray next = spawnRay(si, si.ng);
            ASSERT_TRUE(isFinite(next.origin));
        }
    }
    EXPECT_GT(hits, 100);
    // Both accelerators agree on these rays, up to edge cases.
    CrosscheckReport report = crosscheck(s, *embree, *reference, 5000, 3);
    EXPECT_EQ(report.totalGenuine(), 0u);
}

TEST(HardCases, AcceleratorsAgreeOnFarAwayAndTinyScenes) {
    auto dir = test::scratchDir();
    for (auto [scale, shift] : {std::pair{1.0, Vec3d(1e6, 1e6, -1e6)}, std::pair{1e-3, Vec3d(0.0)},
                                std::pair{1e3, Vec3d(0.0)}}) {
        Scene s = loadScene(writeBoxObj(dir, "box", scale, shift));
        auto embree = makeEmbreeAccelerator(s);
        auto reference = makeReferenceAccelerator(s);
        CrosscheckReport report = crosscheck(s, *embree, *reference, 20000, 5);
        EXPECT_EQ(report.totalGenuine(), 0u) << scale;
    }
}

TEST(Watertightness, WatertightEmbreeAgreesWithTheReferenceRayForRay) {
    // Same triangle test inside Embree's BVH: every crosscheck ray gets the same hit, t and
    // barycentrics as the reference, where default Embree differs at edges (its float test).
    Scene s = loadScene(test::cs184("meshedit/cow.dae"));
    EmbreeOptions opt;
    opt.watertight = true;
    auto embree = makeEmbreeAccelerator(s, opt);
    auto reference = makeReferenceAccelerator(s);
    CrosscheckReport report = crosscheck(s, *embree, *reference, 50000, 5);
    for (const CrosscheckCategory& c : report.categories) {
        EXPECT_EQ(c.agree, c.rays) << int(c.kind);
        EXPECT_EQ(c.maxRelativeDt, 0.0) << int(c.kind);
        EXPECT_EQ(c.maxBaryDiff, 0.0) << int(c.kind);
    }
}

TEST(Degenerate, DuplicateTrianglesLowestIndexWinsInBothAccelerators) {
    // A grid whose every triangle appears three times (the same surface thrice, in another order).
    TriangleMesh grid = test::gridMesh(12, 12, 1.0f);
    std::vector<uint32_t> base = grid.indices;
    for (int copy = 1; copy < 3; ++copy)
        for (size_t t = 0; t < base.size(); t += 3)
            grid.indices.insert(grid.indices.end(),
                                {base[t + size_t(copy)], base[t + (size_t(copy) + 1) % 3],
                                 base[t + (size_t(copy) + 2) % 3]});
    Scene s = test::sceneWith(grid);
    s.duplicateTriangles = countDuplicateTriangles(s);
    uint32_t n = uint32_t(base.size() / 3);
    EXPECT_EQ(s.duplicateTriangles, 2u * n);
    for (int threads : {1, 2, -2}) {  // -2: two threads, --watertight triangles
        EmbreeOptions opt;
        opt.threads = std::abs(threads);
        opt.watertight = threads < 0;
        auto embree = makeEmbreeAccelerator(s, opt);
        auto reference = makeReferenceAccelerator(s);
        int hits = 0;
        for (int i = 0; i < 5000; ++i) {
            Sampler r(6, uint64_t(i), 0);
            Ray ray{Vec3(r.next1D() * 12, r.next1D() * 12, 2), 0,
                    Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, -1), kInfinity};
            Hit a, b;
            bool ha = embree->intersect(ray, a), hb = reference->intersect(ray, b);
            ASSERT_EQ(ha, hb);
            if (!ha) continue;
            ++hits;
            EXPECT_LT(a.prim, n) << "embree picked a later duplicate";
            EXPECT_LT(b.prim, n) << "reference picked a later duplicate";
            EXPECT_EQ(a.prim, b.prim);
        }
        EXPECT_GT(hits, 1000);
    }
}

// --- Deep paths, extreme radiance, non-finite samples
// ----------------------------------------------

TEST(DeepPaths, ThousandBouncesWithoutRouletteStayFinite) {
    TriangleMesh shell = test::sphereMesh(12, 24);
    Scene s = test::sceneWith(shell);
    s.materials[0].albedo = Color(0.5f);
    s.materials[0].emission = Color(1.0f);
    addEmissiveMeshLights(s);
    s.camera.position = Vec3(0.1f, 0.0f, 0.2f);
    s.camera.hFovDeg = s.camera.vFovDeg = 90;
    PathOptions opt;
    opt.maxDepth = 1000;
    opt.roulette = Roulette::Off;
    Film f = renderScene(s, 4, 4, 16, opt);
    Estimate e = blockEstimate(f, 0, 0, 4, 4);
    EXPECT_NEAR(e.mean, 2.0,
                5 * e.se + 1e-4);  // 1 / (1 - 0.5); 0.5^1000 of the tail is far below float
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(f.samples(x, y), 16u);
}

TEST(ExtremeValues, TinyAndHugeRadianceAndZeroAreaLights) {
    float reference = 0;
    for (float radiance : {1e-30f, 1e9f, 1e30f}) {  // 1e9: the sun in absolute units
        Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
        for (Light& l : s.lights) l.radiance = Color(radiance);
        for (Material& m : s.materials) m.emission = m.emission * (radiance / 10.0f);
        auto accel = makeEmbreeAccelerator(s);
        RenderStats stats;
        Film f = test::renderJob(s, *accel, test::jobOptions(24, 18, 4), &stats);
        for (int y = 0; y < 18; ++y)
            for (int x = 0; x < 24; ++x) ASSERT_TRUE(isFinite(f.pixel(x, y)));
        // The film's scale follows the brightest emitter (fixed_sum.h): no sample is dropped.
        EXPECT_EQ(stats.nonFiniteSamples, 0u) << radiance;
        // Same paths, light scaled: each image is the dim one's times its radiance ratio.
        const float at = f.pixel(12, 9).y / radiance;
        if (radiance == 1e-30f) reference = at;
        EXPECT_GT(at, 0.0f) << radiance;
        EXPECT_NEAR(at, reference, 1e-4f * reference) << radiance;
    }
    // A zero-area light: sampling fails cleanly, nothing is NaN.
    Scene s = loadScene(test::cs184("variants/p3-2-sp23/sky/CBspheres_refract.dae"));
    for (Light& l : s.lights) l.dimX = Vec3(0.0f);
    Film f = renderScene(s, 16, 12, 4);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) ASSERT_TRUE(isFinite(f.pixel(x, y)));
}

// An integrator that returns NaN for one known sample: the film drops it and the loop reports it.
class PoisonedIntegrator final : public Integrator {
  public:
    using Integrator::Integrator;
    using Integrator::Li;
    void Li(const Ray& ray, Sampler& sampler, RayCounter& counter, SampleRecord& r) const override {
        r.L = Color(0.5f);
        if (std::abs(ray.dir.x) < 0.02f && std::abs(ray.dir.y) < 0.02f)
            r.L = Color(std::nanf(""), 0, 0);
    }
    const char* name() const override { return "poisoned"; }
};

TEST(NonFinite, CountedReportedForReplayAndNeverWritten) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto accel = makeEmbreeAccelerator(s);
    PoisonedIntegrator integrator(s, *accel);
    RenderSettings settings;
    settings.width = 40, settings.height = 30, settings.spp = 4, settings.progress = false;
    Film f(40, 30, AovRequest::defaults());
    RenderStats stats = renderImage(s, integrator, settings, f);
    ASSERT_GT(stats.nonFiniteSamples, 0u);
    ASSERT_FALSE(stats.firstBadSamples.empty());
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) ASSERT_TRUE(isFinite(f.pixel(x, y)));
    // Every reported sample replays to the same non-finite value.
    for (const BadSample& b : stats.firstBadSamples) {
        RayCounter counter;
        SampleRecord r = traceSample(s, integrator, settings, b.x, b.y, b.sample, counter);
        EXPECT_FALSE(isFinite(r.L)) << b.x << "," << b.y << " sample " << b.sample;
    }
}

}  // namespace
}  // namespace kiln
