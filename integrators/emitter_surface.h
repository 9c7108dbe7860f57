// Light from a surface (LightKind::Area: a CGL rectangle, or the emissive mesh that draws it;
// LightKind::MeshEmitter): uniform by area, one- or two-sided, textured and alpha-cut meshes
// sampled by triangle so a point emits as a ray hitting it sees.
#pragma once

#include <vector>

#include "integrators/light_sample.h"
#include "renderer/core/distribution.h"
#include "scene/scene.h"

namespace kiln {

class SurfaceEmitter {
  public:
    static bool handles(LightKind k) { return k == LightKind::Area || k == LightKind::MeshEmitter; }
    SurfaceEmitter(const Light& l, const Scene& scene);

    float power(float) const {
        return luminance(l_.radiance) * shape_.area * kPi * (shape_.oneSided ? 1.0f : 2.0f);
    }
    bool sample(const Vec3& ref, float u1, float u2, LightSample& out) const;
    float pdf(const Vec3& ref, const Vec3& wi, const Vec3& x, const Vec3& n) const {
        Vec3 d = x - ref;
        float cosL = std::abs(dot(n, wi));
        return cosL > 0 && shape_.area > 0 ? dot(d, d) / (cosL * shape_.area) : 0.0f;
    }
    Color escaped(const Vec3&, bool) const { return Color(0.0f); }
    Color emitted(const Vec3& x, const Vec3&, const Vec3& towards) const {
        if (shape_.oneSided && dot(towards - x, shape_.side) <= 0) return Color(0.0f);
        return l_.radiance;
    }

    // Light leaving the surface (a photon), this light chosen with probability pmf.
    bool sampleEmission(float pmf, float u1, float u2, float uSide, float u3, float u4,
                        EmissionSample& out) const;

  private:
    struct SurfacePoint {
        Vec3 p, pError, n;
        Color texel;  // the emission texture and alpha coverage there
    };
    struct Shape {
        // Triangles with an area distribution.
        std::vector<Vec3> triangles;  // p0, edge1, edge2 per triangle
        std::vector<Vec3> normals;    // unit geometric normal per triangle
        Distribution1D triangleArea;
        // Two triangles tiling a parallelogram: sampled directly (findParallelogram).
        bool parallelogram = false;
        Vec3 origin, edgeX, edgeY, originError, pointError;
        float area = 0;
        bool oneSided = false;
        Vec3 side;  // emitting side for one-sided lights
        // A mesh with an emission texture: sampled by triangle (the point's UVs read the texture).
        bool emissionTextured = false;
        // A mesh whose material cuts it out (alpha mask or blend): a sampled point emits only as
        // much as rays hitting it see (coverageAt), so it too is sampled by triangle.
        bool alphaCut = false;
    };
    SurfacePoint samplePoint(float u1, float u2) const;
    void findParallelogram();
    const Light& l_;
    const Scene* scene_;  // emission textures and alpha of mesh lights
    Shape shape_;
};

}  // namespace kiln
