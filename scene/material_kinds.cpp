#include "scene/material_kinds.h"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

namespace kiln {
namespace {

using P = MaterialParam;
using R = ParamRange;

constexpr P kLambertian[] = {{"albedo", &Material::albedo}};
constexpr P kMirror[] = {{"reflectance", &Material::reflectance}};
constexpr P kGlass[] = {{"ior", nullptr, &Material::ior, R::Positive, true},
                        {"reflectance", &Material::reflectance},
                        {"transmittance", &Material::transmittance},
                        {"roughness", nullptr, &Material::roughness, R::NonNegative}};
constexpr P kRefraction[] = {{"ior", nullptr, &Material::ior, R::Positive, true},
                             {"transmittance", &Material::transmittance},
                             {"roughness", nullptr, &Material::roughness, R::NonNegative}};
constexpr P kMicrofacet[] = {{"alpha", nullptr, &Material::alpha, R::Positive, true},
                             {"eta", &Material::eta, nullptr, R::Any, true},
                             {"k", &Material::k, nullptr, R::Any, true}};
constexpr P kGlossy[] = {{"reflectance", &Material::reflectance},
                         {"shininess", nullptr, &Material::shininess, R::NonNegative}};
constexpr P kEmission[] = {{"radiance", &Material::emission}};
constexpr P kPrincipled[] = {
    {"base-color", &Material::albedo},
    {"metallic", nullptr, &Material::metallic, R::Unit},
    {"roughness", nullptr, &Material::roughness, R::Unit},
    {"specular", nullptr, &Material::specular, R::NonNegative},
    {"ior", nullptr, &Material::ior, R::AtLeastOne},
    {"clearcoat", nullptr, &Material::clearcoat, R::Unit},
    {"clearcoat-roughness", nullptr, &Material::clearcoatRoughness, R::Unit},
    {"specular-color", &Material::specularColor},
    {"transmission", nullptr, &Material::transmission, R::Unit},
    {"thickness", nullptr, &Material::thickness, R::NonNegative},
    {"attenuation-color", &Material::attenuationColor},
    {"attenuation-distance", nullptr, &Material::attenuationDistance, R::Positive},
    {"sheen", nullptr, &Material::sheen, R::Unit},
    {"sheen-color", &Material::sheenColor},
    {"sheen-roughness", nullptr, &Material::sheenRoughness, R::Unit},
    // Subsurface scattering (the random walk: integrators/subsurface.h).
    {"subsurface", nullptr, &Material::subsurface, R::Unit},
    {"subsurface-radius", &Material::subsurfaceRadius, nullptr, R::Any},
    {"subsurface-scale", nullptr, &Material::subsurfaceScale, R::NonNegative}};

bool always(const Material&) { return true; }
bool anyMetal(const Material& m) { return m.metallic > 0; }
bool notAllMetal(const Material& m) { return m.metallic < 1; }
bool principledTransmits(const Material& m) { return m.transmission > 0 && m.metallic < 1; }
bool principledSheen(const Material& m) { return m.sheen > 0 && maxComponent(m.sheenColor) > 0; }
void principledDefaults(Material& m) {
    m.albedo = Color(0.8f);
    m.roughness = 0.5f;
    m.clearcoatRoughness = 0.03f;
}

MaterialKindSpec row(MaterialKind kind, const char* name, std::span<const P> params) {
    MaterialKindSpec s;
    s.kind = kind, s.name = name, s.params = params;
    s.inCgl = true, s.inKiln = true;
    return s;
}

// Indexed by MaterialKind.
std::array<MaterialKindSpec, 8> makeTable() {
    MaterialKindSpec lambertian = row(MaterialKind::Lambertian, "lambertian", kLambertian);
    lambertian.inCgl = false;  // a CGL effect without a CGL element
    lambertian.addsEmission = lambertian.lambertian = true;
    lambertian.countsAsDiffuse = always;

    MaterialKindSpec mirror = row(MaterialKind::Mirror, "mirror", kMirror);
    mirror.deltaSpecular = mirror.mirror = true;

    MaterialKindSpec glass = row(MaterialKind::Glass, "glass", kGlass);
    glass.deltaSpecular = glass.transmission = true;

    MaterialKindSpec microfacet = row(MaterialKind::Microfacet, "microfacet", kMicrofacet);
    microfacet.roughConductor = true;
    microfacet.reflectsGlossily = always;

    MaterialKindSpec refraction = row(MaterialKind::Refraction, "refraction", kRefraction);
    refraction.deltaSpecular = refraction.transmission = true;

    MaterialKindSpec glossy = row(MaterialKind::Glossy, "glossy", kGlossy);
    glossy.glossy = true;
    glossy.reflectsGlossily = always;

    MaterialKindSpec emission = row(MaterialKind::Emission, "emission", kEmission);
    emission.black = true;

    MaterialKindSpec principled = row(MaterialKind::Principled, "principled", kPrincipled);
    principled.inCgl = false;
    principled.addsEmission = principled.glossy = true;
    principled.kilnDefaults = principledDefaults;
    principled.reflectsGlossily = anyMetal;
    principled.countsAsDiffuse = notAllMetal;
    principled.transmits = principledTransmits;
    principled.hasSheen = principledSheen;

    return {lambertian, mirror, glass, microfacet, refraction, glossy, emission, principled};
}

const std::array<MaterialKindSpec, 8>& table() {
    static const std::array<MaterialKindSpec, 8> t = [] {
        auto rows = makeTable();
        for (size_t i = 0; i < rows.size(); ++i)
            if (size_t(rows[i].kind) != i)
                throw std::logic_error("material_kinds: rows out of MaterialKind order");
        return rows;
    }();
    return t;
}

std::string number(float v) { return fmt::format("{:.9g}", v); }

}  // namespace

bool inRange(ParamRange range, float v) {
    switch (range) {
        case ParamRange::Any:
            return true;
        case ParamRange::Positive:
            return v > 0;
        case ParamRange::NonNegative:
            return v >= 0;
        case ParamRange::Unit:
            return v >= 0 && v <= 1;
        case ParamRange::AtLeastOne:
            return v >= 1;
    }
    return false;
}

const char* rangeText(ParamRange range) {
    switch (range) {
        case ParamRange::Any:
            return "finite";
        case ParamRange::Positive:
            return "> 0";
        case ParamRange::NonNegative:
            return ">= 0";
        case ParamRange::Unit:
            return "in [0, 1]";
        case ParamRange::AtLeastOne:
            return ">= 1";
    }
    return "";
}

std::span<const MaterialKindSpec> materialKinds() { return table(); }

const MaterialKindSpec& specOf(MaterialKind kind) { return table().at(size_t(kind)); }

const MaterialKindSpec* findMaterialKind(std::string_view name) {
    for (const MaterialKindSpec& s : table())
        if (name == s.name) return &s;
    return nullptr;
}

std::string materialKindNames(bool (*accepted)(const MaterialKindSpec&)) {
    std::string out;
    for (const MaterialKindSpec& s : table())
        if (accepted(s)) out += (out.empty() ? "" : ", ") + std::string(s.name);
    return out;
}

const char* toString(MaterialKind kind) { return specOf(kind).name; }

std::string describeParams(const Material& m) {
    std::string out;
    for (const MaterialParam& p : specOf(m.kind).params) {
        if (p.colour) {
            const Color& c = m.*p.colour;
            out += fmt::format("{}{} [{}, {}, {}]", out.empty() ? "" : " ", p.name, number(c.x),
                               number(c.y), number(c.z));
        } else {
            out += fmt::format("{}{} {}", out.empty() ? "" : " ", p.name, number(m.*p.scalar));
        }
    }
    return out;
}

}  // namespace kiln
