#include "renderer/validation/crosscheck.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "renderer/geometry/interaction.h"

namespace kiln {
namespace {

// Distance of a hit from the nearest edge of its triangle, in barycentric units (0 = on an edge).
float edgeDistance(const Hit& h) {
    if (h.shape == kSphereShape) return 1.0f;
    return std::min({h.u, h.v, 1.0f - h.u - h.v});
}

// A sphere hit is at the silhouette when the ray grazes it.
bool grazing(const Scene& scene, const Ray& ray, const Hit& h) {
    SurfaceInteraction si = makeInteraction(scene, ray, h);
    float c = std::abs(dot(normalize(ray.dir), si.ng));
    return c < 1e-3f;
}

bool nearEdge(const Scene& scene, const Ray& ray, const Hit& h) {
    return edgeDistance(h) <= kEdgeTolerance || grazing(scene, ray, h);
}

bool samePrimitive(const Hit& a, const Hit& b) {
    return a.shape == b.shape && a.prim == b.prim && a.instance == b.instance;
}

void classify(const Scene& scene, RayComparison& c, bool shadowRay) {
    bool ha = c.a.valid(), hb = c.b.valid();
    if (shadowRay && c.occludedA != c.occludedB) {
        const Hit& h = c.occludedA ? c.a : c.b;
        if (!h.valid()) {
            c.kind = Disagreement::Genuine;
            c.reason = "occlusion differs and the occluding side finds no closest hit";
        } else if (nearEdge(scene, c.ray, h)) {
            c.kind = Disagreement::Edge;
        } else if (std::abs(h.t - c.ray.tMax) <= kTieTolerance * std::max(1.0f, c.ray.tMax)) {
            c.kind = Disagreement::Coplanar;
            c.reason = "occluder at the end of the shadow ray";
        } else {
            c.kind = Disagreement::Genuine;
            c.reason = "occlusion differs";
        }
        return;
    }
    if (!ha && !hb) return;
    if (ha != hb) {
        const Hit& h = ha ? c.a : c.b;
        c.kind = nearEdge(scene, c.ray, h) ? Disagreement::Edge : Disagreement::Genuine;
        if (c.kind == Disagreement::Genuine)
            c.reason = ha ? "second accelerator missed" : "first accelerator missed";
        return;
    }
    c.relativeDt = std::abs(c.a.t - c.b.t) / std::max(std::abs(c.a.t), 1e-30f);
    if (samePrimitive(c.a, c.b)) {
        c.baryDiff = std::max(std::abs(c.a.u - c.b.u), std::abs(c.a.v - c.b.v));
        // Float traversal computes t with an absolute error of a few ulps of the coordinates
        // involved, so a ray starting next to the surface has a large |dt|/t and is still right.
        float coordinateScale =
            maxComponent(abs(c.ray.origin)) + maxComponent(abs(c.ray.origin + c.ray.dir * c.a.t));
        float allowed = kDistanceTolerance * std::abs(c.a.t) +
                        kUlpAllowance * std::numeric_limits<float>::epsilon() * coordinateScale /
                            length(c.ray.dir);
        if (std::abs(c.a.t - c.b.t) > allowed && !grazing(scene, c.ray, c.a)) {
            c.kind = Disagreement::Genuine;
            c.reason = "same primitive, distances differ";
        }
        return;
    }
    if (nearEdge(scene, c.ray, c.a) && nearEdge(scene, c.ray, c.b))
        c.kind = Disagreement::Edge;
    else if (c.relativeDt <= kTieTolerance)
        c.kind = Disagreement::Coplanar;
    else if (nearEdge(scene, c.ray, c.a) || nearEdge(scene, c.ray, c.b)) {
        // One side passed through an edge the other caught: the farther hit is behind that edge.
        c.kind = Disagreement::Edge;
    } else {
        c.kind = Disagreement::Genuine;
        c.reason = "different primitives";
    }
}

}  // namespace

RayComparison compareRay(const Scene& scene, const Accelerator& a, const Accelerator& b,
                         const Ray& ray, bool shadowRay) {
    RayComparison c;
    c.ray = ray;
    a.intersect(ray, c.a);
    b.intersect(ray, c.b);
    if (shadowRay) {
        c.occludedA = a.occluded(ray);
        c.occludedB = b.occluded(ray);
    }
    classify(scene, c, shadowRay);
    return c;
}

CrosscheckReport crosscheck(const Scene& scene, const Accelerator& a, const Accelerator& b,
                            size_t raysPerCategory, uint64_t seed, size_t worstToKeep) {
    CrosscheckReport report;
    for (RaySetKind kind :
         {RaySetKind::Camera, RaySetKind::Random, RaySetKind::Secondary, RaySetKind::Shadow}) {
        std::vector<Ray> rays = makeRaySet(kind, scene, a, raysPerCategory, seed);
        CrosscheckCategory cat;
        cat.kind = kind;
        std::mutex mutex;
        bool shadow = kind == RaySetKind::Shadow;
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, rays.size(), 4096),
            [&](const tbb::blocked_range<size_t>& r) {
                CrosscheckCategory local;
                std::vector<RayComparison> bad;
                for (size_t i = r.begin(); i != r.end(); ++i) {
                    RayComparison c = compareRay(scene, a, b, rays[i], shadow);
                    ++local.rays;
                    local.hitsA += shadow ? c.occludedA : c.a.valid();
                    local.hitsB += shadow ? c.occludedB : c.b.valid();
                    local.samePrim += c.a.valid() && c.b.valid() && samePrimitive(c.a, c.b);
                    local.maxRelativeDt = std::max<double>(
                        local.maxRelativeDt, samePrimitive(c.a, c.b) ? c.relativeDt : 0);
                    local.maxBaryDiff = std::max<double>(local.maxBaryDiff, c.baryDiff);
                    switch (c.kind) {
                        case Disagreement::None:
                            ++local.agree;
                            break;
                        case Disagreement::Edge:
                            ++local.edge;
                            break;
                        case Disagreement::Coplanar:
                            ++local.coplanar;
                            break;
                        case Disagreement::Genuine:
                            ++local.genuine;
                            break;
                    }
                    if (c.kind == Disagreement::Genuine ||
                        (c.kind == Disagreement::None && c.relativeDt > 1e-6f))
                        bad.push_back(c);
                }
                std::lock_guard lock(mutex);
                cat.rays += local.rays, cat.hitsA += local.hitsA, cat.hitsB += local.hitsB;
                cat.agree += local.agree, cat.edge += local.edge, cat.coplanar += local.coplanar;
                cat.genuine += local.genuine, cat.samePrim += local.samePrim;
                cat.maxRelativeDt = std::max(cat.maxRelativeDt, local.maxRelativeDt);
                cat.maxBaryDiff = std::max(cat.maxBaryDiff, local.maxBaryDiff);
                cat.worst.insert(cat.worst.end(), bad.begin(), bad.end());
            });
        // Deterministic order whatever the scheduling: genuine first, then by |dt|/t, then by ray.
        std::sort(
            cat.worst.begin(), cat.worst.end(), [](const RayComparison& x, const RayComparison& y) {
                bool gx = x.kind == Disagreement::Genuine, gy = y.kind == Disagreement::Genuine;
                if (gx != gy) return gx;
                if (x.relativeDt != y.relativeDt) return x.relativeDt > y.relativeDt;
                return formatRay(x.ray) < formatRay(y.ray);
            });
        if (cat.worst.size() > worstToKeep) cat.worst.resize(worstToKeep);
        report.categories.push_back(std::move(cat));
    }
    return report;
}

std::string formatRay(const Ray& r) {
    std::string text;
    for (float v : {r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tMin, r.tMax})
        text += fmt::format("{}{:a}", text.empty() ? "" : " ", double(v));  // exact: hex floats
    return text;
}

// Eight numbers and nothing after; a ray Embree takes: a finite origin, a finite direction that
// is not zero, 0 <= tmin <= tmax (tmax may be infinite), no NaN.
bool parseRay(const std::string& text, Ray& r) {
    const char* p = text.c_str();
    float v[8];
    for (float& x : v) {
        char* end = nullptr;
        x = std::strtof(p, &end);
        if (end == p) return false;
        p = end;
    }
    while (std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (*p != '\0') return false;
    for (int k = 0; k < 7; ++k)
        if (!std::isfinite(v[k])) return false;
    if (v[3] == 0 && v[4] == 0 && v[5] == 0) return false;
    if (!(v[6] >= 0 && v[7] >= v[6])) return false;  // NaN fails too
    r = Ray{Vec3(v[0], v[1], v[2]), v[6], Vec3(v[3], v[4], v[5]), v[7]};
    return true;
}

Json crosscheckJson(const CrosscheckReport& report, const std::string& scenePath) {
    Json categories = Json::array();
    for (const CrosscheckCategory& c : report.categories)
        categories.push_back({{"kind", toString(c.kind)},
                              {"rays", c.rays},
                              {"hits_embree", c.hitsA},
                              {"hits_reference", c.hitsB},
                              {"agree", c.agree},
                              {"edge", c.edge},
                              {"coplanar", c.coplanar},
                              {"genuine", c.genuine},
                              {"max_relative_dt", c.maxRelativeDt},
                              {"max_bary_diff", c.maxBaryDiff}});
    return {{"scene", scenePath}, {"categories", categories}, {"genuine", report.totalGenuine()}};
}

}  // namespace kiln
