#include "integrators/render_plan.h"

#include <fmt/format.h>

#include "renderer/core/sampler.h"
#include "renderer/core/warp.h"
#include "renderer/geometry/camera.h"
#include "renderer/geometry/interaction.h"
#include "scene/light_kinds.h"
#include "scene/material_kinds.h"

namespace kiln {
namespace {

// Fraction of rays that escape from surface points the camera sees, in uniform directions.
float escapeFraction(const Scene& scene, const Accelerator& accel) {
    CameraModel camera(scene.camera, 64, 48);
    int escaped = 0, probes = 0;
    for (int i = 0; i < 4096 && probes < 2048; ++i) {
        Sampler s(1234, uint64_t(i), 0);
        Ray primary = camera.generateRay(s.next1D() * 64, s.next1D() * 48);
        Hit hit;
        if (!accel.intersect(primary, hit)) continue;
        SurfaceInteraction si = makeInteraction(scene, primary, hit);
        Vec3 d = uniformSphere(s.next1D(), s.next1D());
        if (dot(d, si.ng) < 0) d = -d;
        Hit h2;
        ++probes;
        escaped += !accel.intersect(spawnRay(si, d), h2);
    }
    return probes ? float(escaped) / float(probes) : 1.0f;
}

}  // namespace

bool sceneHasMedia(const Scene& scene) {
    for (const TriangleMesh& m : scene.meshes)
        if (m.interior >= 0) return true;
    return false;
}

bool sceneHasSubsurface(const Scene& scene) {
    for (const Material& m : scene.materials)
        if (m.kind == MaterialKind::Principled && m.subsurface > 0) return true;
    return false;
}

RenderPlan generalPlan(const AovRequest& aovs) {
    RenderPlan p;
    p.general = true;
    p.aovs = aovs;
    return p;
}

RenderPlan planFor(const Scene& scene, const Accelerator& accel, const AovRequest& aovs,
                   PlanMode mode) {
    RenderPlan p;
    p.general = mode == PlanMode::General;
    p.aovs = aovs;
    // A flag per material, not a set: every render job (each frame of a batch) scans one id per
    // triangle, and a set's insertions cost 40 ms per million triangles.
    std::vector<char> used(scene.materials.size(), 0);
    for (const TriangleMesh& m : scene.meshes)
        for (uint32_t id : m.materialIds) used[id] = 1;
    for (const Sphere& s : scene.spheres) used[s.material] = 1;
    bool anyDiffuse = false;
    // Mirrors and metals throw an area light's image onto walls.
    bool mirror = false, glossyReflector = false;
    p.diffuseOnly = true;
    for (uint32_t id = 0; id < used.size(); ++id) {
        if (!used[id]) continue;
        const Material& m = scene.materials[id];
        const MaterialKindSpec& k = specOf(m.kind);
        p.deltaSpecular |= k.deltaSpecular;
        bool roughTransmission = k.transmits && k.transmits(m);
        p.transmission |= k.transmission || roughTransmission;
        p.roughTransmission |= roughTransmission;
        p.sheen |= k.hasSheen && k.hasSheen(m);
        p.roughConductor |= k.roughConductor;
        p.glossy |= k.glossy;
        anyDiffuse |= k.lambertian;
        mirror |= k.mirror;
        glossyReflector |= k.reflectsGlossily && k.reflectsGlossily(m);
        p.diffuseOnly &= k.lambertian || k.black;
        p.emitters |= maxComponent(m.emission) > 0;
    }
    bool hittableAreaLights = false;
    p.deltaLightsOnly = !scene.lights.empty();
    for (const Light& l : scene.lights) {
        const LightKindSpec& k = specOf(l.kind);
        p.deltaLightsOnly &= k.delta;
        p.areaLights |= k.surface;
        hittableAreaLights |= k.surface && k.hittable(l);
        p.infiniteLights |= k.infinite;
        p.environmentMap |= l.kind == LightKind::Environment && l.environmentImage != nullptr;
    }
    p.defaultLightSamples = p.environmentMap ? RenderPlan::kEnvironmentLightSamples : 1;
    p.spheres = !scene.spheres.empty();
    p.instances = !scene.instances.empty();
    p.caustics = p.deltaSpecular && anyDiffuse && !scene.lights.empty();
    // Photons leave area lights and emitting meshes only (an environment's caustics stay
    // cosine-sampled). A scene whose only specular surfaces are glass is not guided: seen from
    // where focused light lands, a lens spreads the light's image over much of itself, which
    // cosine sampling finds anyway (docs/light-transport.md: guiding lost on CBgems and
    // CBspheres_refract, won on every scene with a mirror or metal).
    // A mirror's caustic reaches the camera only where its light can be hit (next-event estimation
    // cannot pass a mirror); a metal's also through light sampling at the metal.
    p.guiding = anyDiffuse && ((glossyReflector && p.areaLights) || (mirror && hittableAreaLights));
    p.media = sceneHasMedia(scene);
    p.subsurface = sceneHasSubsurface(scene);
    p.thinLens = scene.camera.apertureRadius > 0;
    p.escapeFraction = escapeFraction(scene, accel);
    p.closed = p.escapeFraction < 0.01f;

    auto say = [&](const std::string& decision, const std::string& reason) {
        p.decisions.push_back(decision + ": " + reason);
    };
    const bool general = p.general;
    if (general) say("general path", "--plan general: every feature on, as a baseline");
    say(p.diffuseOnly && !general ? "Lambert-only shading (no Fresnel, no specular code)"
                                  : "full BSDF set",
        p.diffuseOnly ? "every surface is Lambertian or an emitter"
                      : "the scene has non-Lambertian surfaces");
    if (p.deltaLightsOnly && !p.emitters)
        say(general ? "MIS code kept"
                    : "direct light by light sampling only, no MIS; no continuation ray after the "
                      "last bounce",
            "only point/spot/directional lights and no emitting surface: BSDF-sampled rays can "
            "never find light");
    else
        say("light sampling with MIS against BSDF sampling",
            "the scene has lights that rays can hit");
    if (p.roughTransmission || p.sheen)
        say(std::string("principled lobes: ") + (p.roughTransmission && p.sheen
                                                     ? "transmission and sheen"
                                                 : p.sheen ? "sheen"
                                                           : "transmission"),
            "materials state them; the principled BSDF evaluates each only where its weight is "
            "above 0");
    say(p.infiniteLights || general ? "environment lookup on escape"
                                    : "no environment lookup on escape",
        p.infiniteLights ? "environment or ambient light present"
                         : "no environment or ambient light");
    say(fmt::format("{} light sample{} per shading point unless -l is given", p.defaultLightSamples,
                    p.defaultLightSamples > 1 ? "s" : ""),
        p.environmentMap ? "an environment map lights the scene: measured faster to equal error"
                         : "no environment map");
    if (p.environmentMap)
        say("environment map sampled by its light above half its mean where MIS weighs light "
            "against BSDF samples (--sampling mis, the default)",
            "MIS compensation: BSDF sampling finds the even part of the sky, map samples go to "
            "the bright part it rarely finds");
    say(p.spheres ? "sphere geometry registered" : "no sphere geometry registered",
        p.spheres ? std::to_string(scene.spheres.size()) + " analytic spheres"
                  : "no analytic spheres");
    if (p.instances)
        say("two-level traversal", std::to_string(scene.instances.size()) + " instances");
    if (p.caustics)
        say("caustics reachable only by BSDF sampling",
            "specular (mirror/glass) surfaces and diffuse receivers: "
            "expect noise there, more samples clear it");
    say(p.guiding ? "path guiding of diffuse bounces (unless --guiding off)"
                  : "no path guiding (unless --guiding on)",
        p.guiding ? "mirrors or metals reflect area lights onto diffuse surfaces: cosine "
                    "sampling alone rarely finds that light; photons show where it lands"
                  : "no mirror or metal reflects an area light onto a diffuse surface");
    if (p.media)
        say("participating media: free flights, index-matched boundaries, transmittance on "
            "shadow rays",
            fmt::format("meshes are filled with a medium ({} in the scene)", scene.media.size()));
    if (p.subsurface)
        say("subsurface scattering: random walks inside closed meshes",
            "a principled material has subsurface > 0");
    say(p.thinLens ? "thin-lens camera sampling" : "pinhole camera",
        p.thinLens ? "aperture > 0" : "no aperture");
    say(p.aovs.splitsLight() || general ? "light AOVs accumulated" : "no light AOVs accumulated",
        p.aovs.splitsLight() ? "requested with --aov" : "none requested");
    say(p.closed ? "closed scene: roulette, not escape, ends paths"
                 : "open scene: paths mostly end by escaping",
        fmt::format("{:.1f} % of probe rays from visible surfaces escape",
                    100.0 * p.escapeFraction));
    return p;
}

std::string RenderPlan::text() const {
    std::string out;
    for (const std::string& d : decisions) out += "  " + d + "\n";
    return out;
}

std::string RenderPlan::compact() const {
    std::string out;
    auto flag = [&](bool on, const char* name) {
        if (on) out += std::string(out.empty() ? "" : ",") + name;
    };
    flag(general, "general");
    flag(diffuseOnly, "diffuse-only");
    flag(deltaSpecular, "delta-specular");
    flag(transmission, "transmission");
    flag(roughTransmission, "rough-transmission");
    flag(sheen, "sheen");
    flag(roughConductor, "rough-conductor");
    flag(glossy, "glossy");
    flag(deltaLightsOnly, "delta-lights-only");
    flag(areaLights, "area-lights");
    flag(infiniteLights, "infinite-lights");
    flag(spheres, "spheres");
    flag(instances, "instances");
    flag(caustics, "caustics");
    flag(guiding, "guiding");
    flag(media, "media");
    flag(subsurface, "subsurface");
    flag(thinLens, "thin-lens");
    flag(closed, "closed");
    return out;
}

}  // namespace kiln
