// The render plan: what a scene calls for, derived at load, with the reason for each decision. The
// path tracer is instantiated for it (templates chosen once per render, not per-sample branches).
#pragma once

#include <string>
#include <vector>

#include "renderer/accel/accelerator.h"
#include "renderer/core/enum_names.h"
#include "renderer/film/aov.h"
#include "scene/scene.h"

namespace kiln {

// auto: the path specialised for what the scene holds; general: every feature on.
enum class PlanMode { Auto, General };
template <>
struct EnumNames<PlanMode> {
    static constexpr std::pair<PlanMode, const char*> table[] = {{PlanMode::Auto, "auto"},
                                                                 {PlanMode::General, "general"}};
};

struct RenderPlan {
    // What the scene holds.
    bool diffuseOnly = false;        // every surface Lambertian (or a pure emitter)
    bool deltaSpecular = false;      // mirror / glass / refraction
    bool transmission = false;       // glass / refraction / principled transmission
    bool roughTransmission = false;  // principled transmission (a GGX dielectric lobe)
    bool sheen = false;              // principled sheen (Charlie lobe)
    bool roughConductor = false;     // microfacet
    bool glossy = false;             // Phong glossy or principled (GGX) surfaces
    bool deltaLightsOnly =
        false;                // point / spot / directional only: nothing for BSDF sampling to find
    bool areaLights = false;  // area lights and emissive meshes
    bool infiniteLights = false;  // environment / ambient: rays leaving the scene carry light
    bool environmentMap = false;  // an image-based environment light
    // Light samples per shading point when -l is not given: more for an environment map, where
    // one NEE sample per vertex leaves most of the noise (docs/performance.md: 1 took 2-3x as long
    // as 4 to equal error on the peer benchmark's Lucy; over four map-lit scenes the best count
    // runs from 1 to 8, and 4 stays closest to each one's best); 1 elsewhere (4 lost on the
    // area-lit box).
    int defaultLightSamples = 1;
    static constexpr int kEnvironmentLightSamples = 4;
    bool emitters = false;  // surfaces with emission
    bool spheres = false, instances = false;
    bool caustics = false;  // light can reach a diffuse surface through a specular chain
    // Diffuse bounces follow a trained guide field (guiding.h) unless --guiding says otherwise:
    // where glossy or specular surfaces can carry light onto diffuse ones.
    bool guiding = false;
    // Participating media bounded by meshes, subsurface scattering: the path tracer's
    // specialisation with media (free flights, boundaries, transmittance on shadow rays) only here.
    bool media = false;
    bool subsurface = false;
    bool thinLens = false;
    bool closed = false;  // probe rays from visible surfaces almost never escape
    float escapeFraction = 0;
    AovRequest aovs;
    bool general = false;  // --plan general: every feature on, whatever the scene holds
    std::vector<std::string> decisions;  // "decision: reason", for kiln info and the EXR header

    std::string text() const;     // one decision a line
    std::string compact() const;  // one line for the EXR header
};

// Whether a mesh of the scene bounds a medium; whether a material it uses scatters below its
// surface.
bool sceneHasMedia(const Scene& scene);
bool sceneHasSubsurface(const Scene& scene);

// Every feature on, whatever a scene holds: the baseline specialisations are checked against, and
// what an integrator built without analysis runs.
RenderPlan generalPlan(const AovRequest& aovs = {});

// Scene analysis; accel is used to probe whether the scene is closed.
RenderPlan planFor(const Scene& scene, const Accelerator& accel, const AovRequest& aovs,
                   PlanMode mode = PlanMode::Auto);

}  // namespace kiln
