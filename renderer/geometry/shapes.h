// Ray-primitive tests shared by both accelerators (spheres are user geometry in Embree too, so the
// two agree on them exactly) and by the reference BVH (triangles).
#pragma once

#include <algorithm>
#include <cmath>

#include "renderer/core/ray.h"

namespace kiln {

// Analytic sphere with the numerically stable quadratic (Ray Tracing Gems ch. 7): the discriminant
// is formed from the distance of the centre to the ray line and the near root from c / q, so
// neither cancels for far-away or tiny spheres. Float suffices: on the cases of
// Spheres.AccurateForTinyHugeAndFarAwaySpheres this form is within 4 ulps of the exact distance
// everywhere, where the textbook quadratic fails 6 of 15 (measured, docs/robustness.md). Returns
// the nearest root in (tMin, tMax].
inline bool intersectSphere(const Ray& ray, const Vec3& center, float radius, float& tHit) {
    Vec3 d = ray.dir, f = ray.origin - center;
    float a = dot(d, d);
    float b = -dot(f, d);
    Vec3 l = f + d * (b / a);
    float disc = a * (radius * radius - dot(l, l));
    if (disc < 0) return false;
    float c = dot(f, f) - radius * radius;
    float q = b + std::copysign(std::sqrt(disc), b);
    float t0 = q != 0 ? c / q : 0.0f, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    float t = t0;
    if (!(t > ray.tMin)) t = t1;
    if (!(t > ray.tMin) || !(t <= ray.tMax)) return false;
    tHit = t;
    return true;
}

// Moller-Trumbore in double precision. Exact arithmetic would be watertight with inclusive edges,
// but the rounding of each triangle's own edge tests leaves cracks at shared vertices (measured: a
// ray through a vertex saw -8e-17 .. -1e-14 on all five neighbours). Double rounding on float
// inputs stays below about 1e-12 in barycentric units, so each triangle is grown by
// kBarycentricSlack = 1e-9: every crack closes, and silhouettes move by a billionth of a triangle,
// far below the float precision of the vertices. u, v are the barycentrics of p1 and p2 (clamped
// back onto the triangle).
constexpr double kBarycentricSlack = 1e-9;
inline bool intersectTriangle(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                              float& tHit, float& uHit, float& vHit) {
    Vec3d o(ray.origin), d(ray.dir), v0(p0);
    Vec3d e1 = Vec3d(p1) - v0, e2 = Vec3d(p2) - v0;
    Vec3d pv = cross(d, e2);
    double det = dot(e1, pv);
    if (det == 0) return false;  // parallel or degenerate
    double inv = 1.0 / det;
    Vec3d tv = o - v0;
    double u = dot(tv, pv) * inv;
    if (u < -kBarycentricSlack || u > 1 + kBarycentricSlack) return false;
    Vec3d qv = cross(tv, e1);
    double v = dot(d, qv) * inv;
    if (v < -kBarycentricSlack || u + v > 1 + kBarycentricSlack) return false;
    double t = dot(e2, qv) * inv;
    if (!(t > ray.tMin) || !(t <= ray.tMax)) return false;
    u = std::clamp(u, 0.0, 1.0);
    v = std::clamp(v, 0.0, 1.0 - u);
    tHit = float(t), uHit = float(u), vHit = float(v);
    return true;
}

}  // namespace kiln
