// Light sampling for every light kind, selection by power, and the densities MIS needs.
#pragma once

#include <vector>

#include "renderer/core/distribution.h"
#include "renderer/geometry/interaction.h"
#include "scene/scene.h"

namespace kiln {

// Light leaving an emitting surface (a photon): where it starts, where it goes, and its power
// (the light's radiance over the densities of the point, the direction and the light's choice).
struct EmissionSample {
    SurfaceInteraction from;
    Vec3 dir;
    Color power;
    bool hittable = false;  // rays can hit the light (LightSet::hittable)
};

struct LightSample {
    Color Li;       // radiance arriving at the reference point (before visibility)
    Vec3 wi;        // unit direction towards the light
    Vec3 p;         // point on the light (finite lights)
    Vec3 pError;    // absolute error bound of p
    float pdf = 0;  // solid angle density; 1 for delta lights
    bool delta = false;
    bool infinite = false;  // shadow ray has no end point
};

// A lat-long environment map in memory (scaled, in the working space), looked up bilinearly
// (nearest texel for scenes built without the loader), with its importance-sampling distribution.
struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<Color> pixels;
    Color constant{0.0f};  // used when there is no image (uniform environment)
    Distribution2D distribution;
    float scale = 1;
    float rotation = 0;     // radians about +Y (right-handed: counterclockwise seen from above)
    bool bilinear = false;  // between texel centres (the loader's maps); else nearest texel
    Color lookup(const Vec3& dir) const;
    Color bilinearLookup(float u, float v) const;  // (u, v) in [0,1)^2
    Vec3 direction(float u, float v) const;        // (u, v) in [0,1)^2 -> unit direction
    void coordinates(const Vec3& dir, float& u, float& v) const;
};

class LightSet {
  public:
    explicit LightSet(const Scene& scene);
    size_t size() const { return lights_.size(); }
    const Light& light(size_t i) const { return *lights_[i].light; }

    // Picks a light with probability proportional to its power.
    size_t select(float u, float& pmf) const { return power_.sampleDiscrete(u, pmf); }
    float selectPmf(size_t i) const { return power_.pmf(i); }

    bool sample(size_t i, const Vec3& ref, float u1, float u2, LightSample& out) const;
    // Solid-angle density of sampling direction wi from ref towards light i, given the point hit on
    // it.
    float pdf(size_t i, const Vec3& ref, const Vec3& wi, const Vec3& pointOnLight,
              const Vec3& lightNormal) const;
    // Radiance leaving an emitting surface point towards `towards` (meshes bound to lights and
    // materials).
    Color emitted(size_t i, const Vec3& pointOnLight, const Vec3& lightNormal,
                  const Vec3& towards) const;

    // Whether rays can hit the light (emissive geometry, lights at infinity); NEE alone sees the
    // others.
    bool hittable(size_t i) const;
    // Light bound to a mesh (-1 if none): hits on it are emission MIS can weigh.
    int lightOfMesh(uint32_t mesh) const {
        return mesh < meshLight_.size() ? meshLight_[mesh] : -1;
    }
    // Lights at infinity (environment, ambient) and the radiance each sends along a ray leaving the
    // scene.
    const std::vector<size_t>& infiniteLights() const { return infinite_; }
    Color escaped(size_t i, const Vec3& dir, bool cameraRay) const;
    bool allDelta() const;
    // Light leaving an area light or emitting mesh, chosen by power: a point by area, a
    // cosine-weighted direction on a side it emits from. False where the scene has none.
    bool sampleEmission(float uLight, float u1, float u2, float uSide, float u3, float u4,
                        EmissionSample& out) const;
    // Every emitting surface is a light NEE samples (no emissive sphere, instance or unbound mesh):
    // light sampling alone then accounts for all the light a vertex receives.
    bool everyEmitterSampled() const { return everyEmitterSampled_; }

  private:
    struct Entry {
        const Light* light;
        bool hittable = false;  // light_kinds.h: rays can hit it
        // Area lights (rectangle) and mesh emitters: triangles with an area distribution.
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
        EnvironmentMap env;
    };
    struct SurfacePoint {
        Vec3 p, pError, n;
        Color texel;  // the emission texture and alpha coverage there
    };
    SurfacePoint samplePoint(const Entry& e, float u1, float u2) const;
    float power(const Entry& e, float sceneRadius) const;
    static void findParallelogram(Entry& e);
    const Scene* scene_;  // emission textures of mesh lights
    std::vector<Entry> lights_;
    std::vector<int> meshLight_;
    std::vector<size_t> infinite_;
    Distribution1D power_;
    std::vector<size_t> surfaceEmitters_;  // area lights and emitting meshes, by index
    Distribution1D emitterPower_;          // over surfaceEmitters_
    bool everyEmitterSampled_ = true;
};

}  // namespace kiln
