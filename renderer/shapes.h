// Ray-primitive tests shared by both accelerators (spheres are user geometry in Embree too, so the two
// agree on them exactly) and by the reference BVH (triangles).
#pragma once

#include <cmath>

#include "renderer/ray.h"

namespace kiln {

// Analytic sphere in double precision with the numerically stable quadratic (Ray Tracing Gems ch. 7):
// the discriminant is formed from the distance of the centre to the ray line, avoiding cancellation for
// far-away or tiny spheres. Returns the nearest root in (tMin, tMax].
inline bool intersectSphere(const Ray& ray, const Vec3& center, float radius, float& tHit) {
    Vec3d d(ray.dir), f = Vec3d(ray.origin) - Vec3d(center);
    double a = dot(d, d);
    double b = -dot(f, d);
    Vec3d l = f + d * (b / a);
    double r = radius;
    double disc = a * (r * r - dot(l, l));
    if (disc < 0) return false;
    double c = dot(f, f) - r * r;
    double q = b + std::copysign(std::sqrt(disc), b);
    double t0 = q != 0 ? c / q : 0.0, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    double t = t0;
    if (!(t > ray.tMin)) t = t1;
    if (!(t > ray.tMin) || !(t <= ray.tMax)) return false;
    tHit = float(t);
    return tHit > ray.tMin && tHit <= ray.tMax;
}

// Moller-Trumbore in double precision, edges inclusive (a ray through a shared edge hits one of the two
// triangles rather than slipping between them). u, v are the barycentrics of p1 and p2.
inline bool intersectTriangle(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2, float& tHit,
                              float& uHit, float& vHit) {
    Vec3d o(ray.origin), d(ray.dir), v0(p0);
    Vec3d e1 = Vec3d(p1) - v0, e2 = Vec3d(p2) - v0;
    Vec3d pv = cross(d, e2);
    double det = dot(e1, pv);
    if (det == 0) return false;  // parallel or degenerate
    double inv = 1.0 / det;
    Vec3d tv = o - v0;
    double u = dot(tv, pv) * inv;
    if (u < 0 || u > 1) return false;
    Vec3d qv = cross(tv, e1);
    double v = dot(d, qv) * inv;
    if (v < 0 || u + v > 1) return false;
    double t = dot(e2, qv) * inv;
    if (!(t > ray.tMin) || !(t <= ray.tMax)) return false;
    tHit = float(t), uHit = float(u), vHit = float(v);
    return true;
}

}  // namespace kiln
