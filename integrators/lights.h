// The scene's lights for sampling: one emitter class per light kind (emitter_*.h, registered
// below), selection by power, and the densities MIS needs.
#pragma once

#include <optional>
#include <stdexcept>
#include <type_traits>
#include <variant>
#include <vector>

#include "integrators/emitter_ambient.h"
#include "integrators/emitter_directional.h"
#include "integrators/emitter_environment.h"
#include "integrators/emitter_point.h"
#include "integrators/emitter_surface.h"
#include "integrators/light_sample.h"
#include "renderer/core/distribution.h"
#include "scene/scene.h"

namespace kiln {

template <class... Classes>
struct EmitterClasses {
    using Variant = std::variant<Classes...>;
    // The class whose handles() takes the light's kind (the first that does).
    static Variant make(const Light& l, const Scene& scene, const LightSetOptions& o) {
        std::optional<Variant> v;
        (void)((Classes::handles(l.kind) ? (emplace<Classes>(v, l, scene, o), true) : false) ||
               ...);
        if (!v) throw std::logic_error("lights: no emitter class for a light kind");
        return std::move(*v);
    }
    // The options go to the classes whose constructors take them.
    template <class C>
    static void emplace(std::optional<Variant>& v, const Light& l, const Scene& scene,
                        const LightSetOptions& o) {
        if constexpr (std::is_constructible_v<C, const Light&, const Scene&,
                                              const LightSetOptions&>)
            v.emplace(std::in_place_type<C>, l, scene, o);
        else
            v.emplace(std::in_place_type<C>, l, scene);
    }
    // How many classes take the kind (exactly one: tests/test_material_kinds.cpp).
    static int handlerCount(LightKind k) { return (int(Classes::handles(k)) + ...); }
};

// The registration: every emitter class, one entry each (a new light kind's class goes here).
using RegisteredEmitters = EmitterClasses<SurfaceEmitter, PointEmitter, DirectionalEmitter,
                                          AmbientEmitter, EnvironmentEmitter>;

class LightSet {
  public:
    explicit LightSet(const Scene& scene, const LightSetOptions& options = {});
    size_t size() const { return lights_.size(); }
    const Light& light(size_t i) const { return *lights_[i].light; }

    // Picks a light with probability proportional to its power.
    size_t select(float u, float& pmf) const { return power_.sampleDiscrete(u, pmf); }
    float selectPmf(size_t i) const { return power_.pmf(i); }

    bool sample(size_t i, const Vec3& ref, float u1, float u2, LightSample& out) const;
    // Asks memory for what sample(i, ., u1, u2) reads first, where that is a cache miss worth
    // overlapping with other samples' (an environment map's tables); nothing for other lights.
    void prefetch(size_t i, float u1, float u2) const {
        if (const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter))
            env->prefetch(u1, u2);
    }
    // sample() of an environment light in two steps (EnvironmentEmitter::locate): locate is false
    // for other lights (sample() them) and where the map gives no point.
    bool locate(size_t i, float u1, float u2, EnvironmentSample& out) const {
        const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter);
        return env && env->locate(u1, u2, out);
    }
    // prefetch that keeps what it computed: an environment map's row, true (locateInRow then
    // finishes the point); false for other lights (prefetch did nothing for them either).
    bool pickRow(size_t i, float u1, float u2, EnvironmentSample& out) const {
        const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter);
        return env && env->pickRow(u1, u2, out);
    }
    bool locateInRow(size_t i, float u1, EnvironmentSample& out) const {
        return std::get<EnvironmentEmitter>(lights_[i].emitter).locateInRow(u1, out);
    }
    bool sampleLocated(size_t i, const EnvironmentSample& s, LightSample& out) const {
        out = LightSample{};
        return std::get<EnvironmentEmitter>(lights_[i].emitter).sampleLocated(s, out);
    }
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
    // escaped() of a ray from ref, and pdf(i, ref, dir, .) for MIS (an environment map looks its
    // coordinates up once for both).
    Color escaped(size_t i, const Vec3& ref, const Vec3& dir, bool cameraRay, float& pdf) const;
    // The two escaped() from dir's coordinates found already (latLong4), pdf null for the first:
    // the same values, for a batch of rays whose coordinates were found four at once.
    Color escaped(size_t i, const Vec3& ref, const Vec3& dir, const LatLong& ll, bool cameraRay,
                  float* pdf) const;
    // Asks memory for what escaped(i, ., ., ll, ., .) reads (an environment map's texels and
    // table entries); nothing for other lights.
    void prefetchEscape(size_t i, const LatLong& ll) const {
        if (const auto* env = std::get_if<EnvironmentEmitter>(&lights_[i].emitter))
            env->prefetchEscape(ll);
    }
    bool allDelta() const;
    // Light leaving an area light or emitting mesh, chosen by power: a point by area, a
    // cosine-weighted direction on a side it emits from. False where the scene has none.
    bool sampleEmission(float uLight, float u1, float u2, float uSide, float u3, float u4,
                        EmissionSample& out) const;
    // Every emitting surface is a light NEE samples (no emissive sphere, instance or unbound mesh):
    // light sampling alone then accounts for all the light a vertex receives.
    bool everyEmitterSampled() const { return everyEmitterSampled_; }
    // An environment map is sampled MIS-compensated with lit texels cut to 0: light sampling
    // alone would miss their light.
    bool anyCompensated() const;

  private:
    struct Entry {
        const Light* light;
        bool hittable = false;  // light_kinds.h: rays can hit it
        RegisteredEmitters::Variant emitter;
        template <class F>
        decltype(auto) visit(F&& f) const {
            return std::visit(std::forward<F>(f), emitter);
        }
    };
    std::vector<Entry> lights_;
    std::vector<int> meshLight_;
    std::vector<size_t> infinite_;
    Distribution1D power_;
    std::vector<size_t> surfaceEmitters_;  // area lights and emitting meshes, by index
    Distribution1D emitterPower_;          // over surfaceEmitters_
    bool everyEmitterSampled_ = true;
};

}  // namespace kiln
