#include "integrators/lights.h"

#include "scene/light_kinds.h"

namespace kiln {
namespace {

bool emits(const Scene& scene, uint32_t material) {
    return maxComponent(scene.materials[material].emission) > 0;
}

// An emitting surface no light samples: a sphere, an instanced mesh or a mesh bound to no light.
bool hasUnsampledEmitter(const Scene& scene, const std::vector<int>& meshLight) {
    for (const Sphere& s : scene.spheres)
        if (emits(scene, s.material)) return true;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (meshLight[m] >= 0) continue;  // prototypes (instanced meshes) are bound to none
        for (uint32_t id : scene.meshes[m].materialIds)
            if (emits(scene, id)) return true;
    }
    return false;
}

}  // namespace

LightSet::LightSet(const Scene& scene, const LightSetOptions& options) {
    std::vector<bool> proto = scene.prototypeMask();
    meshLight_.assign(scene.meshes.size(), -1);
    // An infinite light's power, weighed against other lights', is over the scene's bounding
    // sphere; a light alone is picked every time, and its radius is not worth a pass over every
    // vertex per frame (1 ms a frame of a 1M-vertex turntable).
    float radius = 1.0f;
    if (scene.lights.size() > 1)
        if (Bounds3 b = scene.storedBounds(); !b.empty()) radius = 0.5f * length(b.diagonal());
    for (const Light& l : scene.lights) {
        const LightKindSpec& kind = specOf(l.kind);
        // A mesh drawn by itself (not only through instances) is hit as this light.
        if (kind.surface && (l.kind == LightKind::MeshEmitter || l.hasMesh) && !proto[l.mesh])
            meshLight_[l.mesh] = int(lights_.size());
        if (kind.infinite) infinite_.push_back(lights_.size());
        lights_.push_back({&l, kind.hittable(l), RegisteredEmitters::make(l, scene, options)});
    }
    everyEmitterSampled_ = !hasUnsampledEmitter(scene, meshLight_);
    std::vector<float> powers, emitterPowers;
    for (size_t i = 0; i < lights_.size(); ++i) {
        powers.push_back(lights_[i].visit([&](const auto& e) { return e.power(radius); }));
        if (specOf(lights_[i].light->kind).surface) {
            surfaceEmitters_.push_back(i);
            emitterPowers.push_back(powers.back());
        }
    }
    power_ = Distribution1D(powers);
    emitterPower_ = Distribution1D(emitterPowers);
}

bool LightSet::hittable(size_t i) const { return lights_[i].hittable; }

bool LightSet::anyCompensated() const {
    for (const Entry& e : lights_)
        if (const auto* env = std::get_if<EnvironmentEmitter>(&e.emitter);
            env && env->compensated())
            return true;
    return false;
}

bool LightSet::allDelta() const {
    for (const Entry& e : lights_)
        if (!specOf(e.light->kind).delta) return false;
    return true;
}

Color LightSet::emitted(size_t i, const Vec3& x, const Vec3& n, const Vec3& towards) const {
    return lights_[i].visit([&](const auto& e) { return e.emitted(x, n, towards); });
}

bool LightSet::sampleEmission(float uLight, float u1, float u2, float uSide, float u3, float u4,
                              EmissionSample& out) const {
    float pmf;
    size_t i = surfaceEmitters_.empty() ? 0 : emitterPower_.sampleDiscrete(uLight, pmf);
    if (surfaceEmitters_.empty() || pmf <= 0) return false;
    const Entry& e = lights_[surfaceEmitters_[i]];
    const auto* surface = std::get_if<SurfaceEmitter>(&e.emitter);
    if (!surface) return false;
    out.hittable = e.hittable;
    return surface->sampleEmission(pmf, u1, u2, uSide, u3, u4, out);
}

bool LightSet::sample(size_t i, const Vec3& ref, float u1, float u2, LightSample& out) const {
    out = LightSample{};
    return lights_[i].visit([&](const auto& e) { return e.sample(ref, u1, u2, out); });
}

float LightSet::pdf(size_t i, const Vec3& ref, const Vec3& wi, const Vec3& x, const Vec3& n) const {
    return lights_[i].visit([&](const auto& e) { return e.pdf(ref, wi, x, n); });
}

Color LightSet::escaped(size_t i, const Vec3& dir, bool cameraRay) const {
    return lights_[i].visit([&](const auto& e) { return e.escaped(dir, cameraRay); });
}

Color LightSet::escaped(size_t i, const Vec3& ref, const Vec3& dir, const LatLong& ll,
                        bool cameraRay, float* pdf) const {
    if (const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter))
        return env->escapedAt(dir, ll, pdf);
    return pdf ? escaped(i, ref, dir, cameraRay, *pdf) : escaped(i, dir, cameraRay);
}

Color LightSet::escaped(size_t i, const Vec3& ref, const Vec3& dir, bool cameraRay,
                        float& pdf) const {
    if (const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter))
        return env->escaped(dir, pdf);
    pdf = this->pdf(i, ref, dir, Vec3(0.0f), Vec3(0.0f));
    return escaped(i, dir, cameraRay);
}

}  // namespace kiln
