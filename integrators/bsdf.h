// The BSDF of a surface point, whatever its material kind: a closed set of per-kind BSDF classes,
// each in its own file, dispatched by kind. Every class evaluates in the local shading frame (z =
// the shading normal as the file orients it, so z < 0 is "inside" for dielectrics); sampling, pdf
// and evaluation agree (chi-square tests). The kinds themselves are described in
// scene/material_kinds.h.
#pragma once

#include <variant>

#include "integrators/bsdf_black.h"
#include "integrators/bsdf_conductor.h"
#include "integrators/bsdf_dielectric.h"
#include "integrators/bsdf_lambert.h"
#include "integrators/bsdf_mirror.h"
#include "integrators/bsdf_phong.h"
#include "integrators/principled_bsdf.h"
#include "renderer/geometry/interaction.h"

namespace kiln {

template <class... Classes>
struct BsdfClasses {
    using Variant = std::variant<Classes...>;
    // Constructs the class whose handles() takes m.kind (the first that does).
    static void construct(Variant& v, const Material& m, MicrofacetModel model,
                          const SurfaceInputs& in) {
        (void)((Classes::handles(m.kind) ? (v.template emplace<Classes>(m, model, in), true)
                                         : false) ||
               ...);
    }
    // How many classes take the kind (exactly one for every kind: tests/test_material_kinds.cpp).
    static int handlerCount(MaterialKind k) { return (int(Classes::handles(k)) + ...); }
    static Color aovAlbedo(const Material& m, const Color& baseColour) {
        Color out(0.0f);
        (void)((Classes::handles(m.kind) ? (out = Classes::aovAlbedo(m, baseColour), true)
                                         : false) ||
               ...);
        return out;
    }
};

// The registration: every BSDF class, one entry each (a new kind's class goes here).
using RegisteredBsdfs = BsdfClasses<LambertBsdf, MirrorBsdf, DielectricBsdf, ConductorBsdf,
                                    PhongBsdf, BlackBsdf, PrincipledBsdf>;

class Bsdf {
    RegisteredBsdfs::Variant v_;
    template <class F>
    decltype(auto) visit(F&& f) const {
        return std::visit(std::forward<F>(f), v_);
    }

  public:
    explicit Bsdf(const Material& material, MicrofacetModel model = MicrofacetModel::Beckmann)
        : Bsdf(material, model, SurfaceInputs::of(material)) {}
    // in: the material at this point (textures, vertex colours: material_lookup.h).
    Bsdf(const Material& material, MicrofacetModel model, const SurfaceInputs& in)
        : v_(std::in_place_type<BlackBsdf>, material, model, in) {
        RegisteredBsdfs::construct(v_, material, model, in);
    }
    // What the albedo AOV records for a material whose base colour here is baseColour.
    static Color aovAlbedo(const Material& m, const Color& baseColour) {
        return RegisteredBsdfs::aovAlbedo(m, baseColour);
    }

    bool isDelta() const {
        return visit([](const auto& b) { return b.isDelta(); });
    }
    bool isBlack() const {
        return visit([](const auto& b) { return b.isBlack(); });
    }
    bool isDiffuse() const {
        return visit([](const auto& b) { return b.isDiffuse(); });
    }
    // sample() reads uc (a lobe to choose: glass, principled); else the caller skips drawing it.
    bool usesLobeChoice() const {
        return visit([](const auto& b) { return b.usesLobeChoice(); });
    }
    bool hasTransmission() const {
        return visit([](const auto& b) { return b.hasTransmission(); });
    }
    Color eval(const Vec3& wo, const Vec3& wi) const {  // local directions; 0 for delta lobes
        return visit([&](const auto& b) { return b.eval(wo, wi); });
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {  // 0 for delta lobes
        return visit([&](const auto& b) { return b.pdf(wo, wi); });
    }
    // uc picks a lobe (glass, principled), (u1, u2) the direction. False when no direction is
    // produced.
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const {
        if (wo.z == 0) return false;
        out = BsdfSample{};
        return visit([&](const auto& b) { return b.sample(wo, uc, u1, u2, out); });
    }
};

// The frame a vertex shades in, seen from woWorld. A shading normal bent so far that the viewer is
// below its tangent plane would make the surface black: such a vertex shades with the geometric
// normal instead (on the stored normal's side).
inline Frame shadingFrame(const SurfaceInteraction& si, const Vec3& woWorld) {
    if (dot(woWorld, si.ns) > 0) return Frame(si.nsStored);
    return Frame(dot(si.ns, si.nsStored) >= 0 ? si.ng : -si.ng);
}

}  // namespace kiln
