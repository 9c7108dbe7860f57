// Both accelerators: construction edge cases, agreement ray by ray, spheres, instancing,
// watertightness.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>

#include "renderer/accel/bvh.h"
#include "renderer/accel/reference_bvh.h"
#include "renderer/cli/accel_options.h"
#include "renderer/core/sampler.h"
#include "renderer/geometry/interaction.h"
#include "renderer/geometry/shapes.h"
#include "renderer/validation/crosscheck.h"
#include "renderer/validation/ray_sets.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

using test::gridMesh;
using test::sceneWith;
using test::sphereMesh;

TEST(ReferenceBvh, DegenerateSplitsNeverCrash) {
    // 1000 copies of the same triangle: every centroid equal, no spatial split exists.
    TriangleMesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 1000; ++i) m.indices.insert(m.indices.end(), {0, 1, 2});
    m.materialIds = {0};
    m.finalizePadding();
    Scene s = sceneWith(m);
    for (BvhSplit split : {BvhSplit::Sah, BvhSplit::MeanCentroid, BvhSplit::Midpoint})
        for (int leaf : {1, 2, 4, 16, 255}) {
            ReferenceAccelerator accel(s, ReferenceBvhOptions{split, leaf});
            Hit hit;
            ASSERT_TRUE(
                accel.intersect(Ray{Vec3(0.2f, 0.2f, 1), 0, Vec3(0, 0, -1), kInfinity}, hit));
            EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
            EXPECT_LE(accel.topLevelStatistics().maxDepth, 128u);
        }
}

TEST(ReferenceBvh, EmptySceneAndEveryLeafSizeAgree) {
    Scene s = sceneWith(gridMesh(30, 30, 0.1f));
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i) {
        Sampler r(3, uint64_t(i), 0);
        rays.push_back(Ray{Vec3(r.next1D() * 3, r.next1D() * 3, 1), 0,
                           Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, -1), kInfinity});
    }
    ReferenceAccelerator base(s, ReferenceBvhOptions{});
    for (BvhSplit split : {BvhSplit::Sah, BvhSplit::MeanCentroid, BvhSplit::Midpoint})
        for (int leaf : {1, 3, 8, 64}) {
            ReferenceAccelerator accel(s, ReferenceBvhOptions{split, leaf});
            for (const Ray& ray : rays) {
                Hit a, b;
                bool ha = base.intersect(ray, a), hb = accel.intersect(ray, b);
                ASSERT_EQ(ha, hb);
                if (ha) {
                    EXPECT_EQ(a.t, b.t);
                }
            }
        }
}

TEST(ReferenceBvh, SahBeatsMeanCentroidOnARealMesh) {
    Scene s = loadScene(test::cs184("meshedit/cow.dae"));
    ReferenceAccelerator sah(s, ReferenceBvhOptions{BvhSplit::Sah, 4});
    ReferenceAccelerator mean(s, ReferenceBvhOptions{BvhSplit::MeanCentroid, 4});
    BvhStatistics a = sah.topLevelStatistics(), b = mean.topLevelStatistics();
    EXPECT_GT(a.nodes, 0u);
    EXPECT_LT(a.sahCost, b.sahCost);
}

TEST(Spheres, AccurateForTinyHugeAndFarAwaySpheres) {
    for (double radius : {1e-4, 1e-2, 1.0, 1e2, 1e4})
        for (double offset : {0.0, 1e3, 1e5}) {
            Vec3 centre(float(offset), float(-offset), float(offset * 0.5));
            // Ray from at least 10 radii away towards the centre, slightly off-axis (0.3 radius).
            Vec3 origin = centre + Vec3(float(0.3 * radius), 0, float(std::max(10 * radius, 10.0)));
            Ray ray{origin, 0, Vec3(0, 0, -1), kInfinity};
            float t;
            ASSERT_TRUE(intersectSphere(ray, centre, float(radius), t)) << radius << " " << offset;
            // Exact (double) answer for the same float inputs.
            double dz = double(origin.z) - double(centre.z),
                   dx = double(origin.x) - double(centre.x);
            double exact = dz - std::sqrt(double(float(radius)) * double(float(radius)) - dx * dx);
            // Only the final rounding to float may separate the two: a few ulps of t.
            EXPECT_NEAR(t, exact, 4 * std::numeric_limits<float>::epsilon() * exact)
                << "radius " << radius << " offset " << offset;
            // A ray spawned from that hit point outwards must not hit the sphere again.
            Scene s;
            s.materials.push_back(Material{});
            s.spheres.push_back(Sphere{"s", centre, float(radius), 0});
            Hit hit{t, 0, 0, kSphereShape, 0, kInvalidId};
            SurfaceInteraction si = makeInteraction(s, ray, hit);
            Ray out = spawnRay(si, si.ng);
            float t2;
            EXPECT_FALSE(intersectSphere(out, centre, float(radius), t2)) << "re-hit at " << t2;
        }
}

TEST(Instancing, InstancedAndFlattenedScenesHitTheSameSurfaces) {
    TriangleMesh ball = sphereMesh(16, 32);
    Scene inst = sceneWith(ball);
    Scene flat;
    flat.sourcePath = "flat";
    flat.materials.push_back(Material{"m"});
    for (int i = 0; i < 9; ++i) {
        Mat4 xf;
        xf.m[0][0] = xf.m[1][1] = xf.m[2][2] = 0.4 + 0.05 * i;
        xf.m[0][3] = (i % 3) * 3.0, xf.m[1][3] = (i / 3) * 3.0, xf.m[2][3] = -2.0;
        inst.instances.push_back(Instance::place(0, xf));
        TriangleMesh copy = ball;
        for (size_t v = 0; v < copy.vertexCount(); ++v) {
            Vec3 p = xf.point(copy.vertex(uint32_t(v)));
            copy.positions[3 * v] = p.x, copy.positions[3 * v + 1] = p.y,
                               copy.positions[3 * v + 2] = p.z;
        }
        flat.meshes.push_back(copy);
    }
    EXPECT_EQ(inst.instancedTriangles(), flat.uniqueTriangles());
    auto embreeInst = makeEmbreeAccelerator(inst), embreeFlat = makeEmbreeAccelerator(flat);
    auto refInst = makeReferenceAccelerator(inst), refFlat = makeReferenceAccelerator(flat);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        Sampler r(5, uint64_t(i), 0);
        Ray ray{Vec3(r.next1D() * 8 - 1, r.next1D() * 8 - 1, 5), 0, Vec3(0, 0, -1), kInfinity};
        Hit a, b, c, d;
        bool ha = embreeInst->intersect(ray, a), hb = embreeFlat->intersect(ray, b);
        bool hc = refInst->intersect(ray, c), hd = refFlat->intersect(ray, d);
        ASSERT_EQ(ha, hb);
        ASSERT_EQ(hc, hd);
        ASSERT_EQ(ha, hc);
        if (!ha) continue;
        ++hits;
        // Instances report the prototype mesh and their instance index; flattened copies their
        // mesh.
        EXPECT_EQ(a.instance, b.shape);
        EXPECT_EQ(c.instance, d.shape);
        EXPECT_EQ(a.prim, b.prim);
        EXPECT_NEAR(a.t, b.t, 1e-4f * a.t);
        EXPECT_NEAR(c.t, d.t, 1e-4f * c.t);
        SurfaceInteraction si = makeInteraction(inst, ray, c), sf = makeInteraction(flat, ray, d);
        EXPECT_NEAR(length(si.p - sf.p), 0.0f, 1e-4f);
        EXPECT_GT(dot(si.ng, sf.ng), 0.9999f);
    }
    EXPECT_GT(hits, 2000);
}

TEST(Watertight, RaysThroughSharedEdgesAndVerticesNeverLeak) {
    // Rays aimed exactly at the shared edges and vertices of a closed tessellated sphere, arriving
    // from outside within 60 degrees of the outward normal (a grazing ray may legitimately pass the
    // rounded target), must hit: Embree with RTC_SCENE_FLAG_ROBUST (our default) and the reference
    // test both.
    TriangleMesh ball = sphereMesh(24, 48);
    Scene s = sceneWith(ball);
    auto embree = makeEmbreeAccelerator(s);
    auto reference = makeReferenceAccelerator(s);
    int leaksEmbree = 0, leaksReference = 0, rays = 0;
    const TriangleMesh& m = s.meshes[0];
    for (size_t t = 0; t < m.triangleCount(); ++t)
        for (int e = 0; e < 3; ++e) {
            Vec3 a = m.vertex(m.indices[3 * t + e]), b = m.vertex(m.indices[3 * t + (e + 1) % 3]);
            for (float f : {0.0f, 0.25f, 0.5f}) {
                Vec3 target = a + (b - a) * f;
                for (int k = 0; k < 3; ++k) {
                    Sampler r(11, t * 3 + e, uint64_t(k));
                    Vec3 jitter =
                        Vec3(r.next1D() - 0.5f, r.next1D() - 0.5f, r.next1D() - 0.5f) * 1.2f;
                    Vec3 out = normalize(normalize(target) + jitter);
                    if (dot(out, normalize(target)) < 0.5f) continue;  // keep within 60 degrees
                    Vec3 from = target + out * (1.0f + 3.0f * r.next1D());
                    Ray ray{from, 0, target - from, kInfinity};
                    Hit h;
                    ++rays;
                    leaksEmbree += !embree->intersect(ray, h);
                    leaksReference += !reference->intersect(ray, h);
                }
            }
        }
    EXPECT_GT(rays, 25000);
    EXPECT_EQ(leaksEmbree, 0);
    EXPECT_EQ(leaksReference, 0);
}

class Cs184Crosscheck : public ::testing::TestWithParam<const char*> {};

TEST_P(Cs184Crosscheck, NoGenuineMismatches) {
    Scene s = loadScene(test::cs184(GetParam()));
    auto embree = makeEmbreeAccelerator(s);
    auto reference = makeReferenceAccelerator(s);
    CrosscheckReport report = crosscheck(s, *embree, *reference, 20000, 1);
    for (const CrosscheckCategory& c : report.categories) {
        EXPECT_EQ(c.genuine, 0u) << toString(c.kind);
        EXPECT_EQ(c.rays, 20000u) << toString(c.kind);
        // Disagreements of any kind are rare: they need a ray within 1e-5 of an edge.
        EXPECT_LE(c.edge + c.coplanar, c.rays / 200) << toString(c.kind);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Cs184Crosscheck,
                         ::testing::Values("sky/CBspheres.dae", "sky/CBbunny.dae", "sky/CBgems.dae",
                                           "sky/CBcoil.dae", "keenan/banana.dae",
                                           "meshedit/teapot.dae"),
                         [](const auto& info) {
                             std::string n = info.param;
                             for (char& c : n)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

TEST(EmbreeBatches, PacketsGiveTheSameHitsAsSingleRays) {
    for (const char* scene : {"sky/CBspheres.dae", "sky/CBbunny.dae"}) {
        Scene s = loadScene(test::cs184(scene));
        auto embree = makeEmbreeAccelerator(s);
        std::vector<Ray> rays = makeRaySet(RaySetKind::Camera, s, *embree, 1000, 3);
        std::vector<Ray> shadow = makeRaySet(RaySetKind::Shadow, s, *embree, 1000, 3);
        rays.resize(999);  // not a multiple of 16: the last packet is partly masked
        std::vector<Hit> hits(rays.size());
        embree->intersect(std::span<const Ray>(rays), std::span<Hit>(hits));
        int hitCount = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            Hit single;
            bool h = embree->intersect(rays[i], single);
            ASSERT_EQ(h, hits[i].valid()) << scene << " ray " << i;
            if (!h) continue;
            ++hitCount;
            EXPECT_EQ(single.shape, hits[i].shape);
            EXPECT_EQ(single.prim, hits[i].prim);
            EXPECT_NEAR(single.t, hits[i].t, 1e-5f * single.t);
        }
        EXPECT_GT(hitCount, 200);  // the box fills about a third of the course framing
        std::vector<uint8_t> occ(shadow.size());
        embree->occluded(std::span<const Ray>(shadow), std::span<uint8_t>(occ));
        for (size_t i = 0; i < shadow.size(); ++i)
            EXPECT_EQ(occ[i] != 0, embree->occluded(shadow[i])) << i;
    }
}

// A render's -t bounds Embree's build too: Embree holds the count as a TBB global_control while
// the device lives; without a count (tests, crosscheck) it takes every core as before.
TEST(EmbreeThreads, TheBuildKeepsToTheRendersThreads) {
    Scene s = loadScene(test::cs184("sky/CBspheres.dae"));
    auto parallelism = [] {
        return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    };
    const size_t before = parallelism();
    ASSERT_GT(before, 1u) << "needs a machine with two cores or more";
    const AcceleratorChoice all;
    EXPECT_EQ(all.withThreads(0), all);
    EXPECT_EQ(all.withThreads(1).embree.threads, 1);
    EXPECT_EQ(all.withThreads(1 << 20).embree.threads,
              tbb::info::default_concurrency());  // at most the cores
    {
        std::unique_ptr<Accelerator> accel = all.withThreads(1).build(s);
        EXPECT_EQ(parallelism(), 1u);
    }
    EXPECT_EQ(parallelism(), before);
    {
        std::unique_ptr<Accelerator> accel = all.build(s);
        EXPECT_EQ(parallelism(), before);
    }
}

TEST(Crosscheck, RayTextRoundTripsExactly) {
    Ray r{Vec3(0.1f, -3e7f, 1e-30f), 1e-4f, Vec3(1.0f / 3, 2, -0.5f), kInfinity};
    Ray back;
    ASSERT_TRUE(parseRay(formatRay(r), back));
    EXPECT_EQ(back.origin, r.origin);
    EXPECT_EQ(back.dir, r.dir);
    EXPECT_EQ(back.tMin, r.tMin);
    EXPECT_EQ(back.tMax, r.tMax);
}

}  // namespace
}  // namespace kiln
