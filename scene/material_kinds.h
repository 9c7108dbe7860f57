// One description per material kind: its parameters (how every reader reads them and how kiln info
// prints them), and what the render plan and the integrators learn from a surface of that kind.
// Readers (scene/cgl_extras, scene/kiln_scene), kiln info and the render plan go through this
// table; the kind's BSDF is registered in integrators/bsdf.h. A new kind is a row here, its BSDF
// class and its test (docs/architecture.md, "Where a new feature goes").
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace kiln {

// The values a parameter may take; every reader refuses others with the same rule.
enum class ParamRange { Any, Positive, NonNegative, Unit, AtLeastOne };
bool inRange(ParamRange range, float v);
const char* rangeText(ParamRange range);  // "> 0", "in [0, 1]", ...

// One parameter: the attribute of a .kiln <material>, the child element of a CGL <technique>
// element and the word kiln info prints, all one name.
struct MaterialParam {
    const char* name;
    Color Material::*colour = nullptr;  // a colour (r g b) ...
    float Material::*scalar = nullptr;  // ... or a number
    ParamRange range = ParamRange::Any;
    bool requiredInKiln = false;  // .kiln: absent means the kind's default unless required
};

struct MaterialKindSpec {
    MaterialKind kind;
    const char* name;  // kiln info, .kiln kind="...", the CGL element
    std::span<const MaterialParam> params;
    bool inCgl = false;         // a CS184 <technique profile="CGL"> element (every param required)
    bool inKiln = false;        // a .kiln kind
    bool addsEmission = false;  // .kiln emission="r g b" is added to what it reflects
    // The kind's defaults before a .kiln file's attributes (else Material{}'s).
    void (*kilnDefaults)(Material&) = nullptr;

    // What a surface of this kind is, for the render plan and the integrators.
    bool lambertian = false;     // the Lambert-only code path
    bool black = false;          // reflects nothing (a pure emitter)
    bool deltaSpecular = false;  // a delta lobe (mirror, smooth glass)
    bool transmission = false;
    bool mirror = false;  // throws a hittable light's image (caustic guiding)
    bool roughConductor = false;
    bool glossy = false;
    // Reflects light glossily onto other surfaces (guiding's caustics), for this material.
    bool (*reflectsGlossily)(const Material&) = nullptr;
    // Light it reflects counts in the diffuse lobe AOVs (else the specular ones), for this
    // material.
    bool (*countsAsDiffuse)(const Material&) = nullptr;
    // Transmits light for this material although the kind may not (principled transmission).
    bool (*transmits)(const Material&) = nullptr;
    // Has a sheen lobe, for this material (principled sheen).
    bool (*hasSheen)(const Material&) = nullptr;
};

std::span<const MaterialKindSpec> materialKinds();
const MaterialKindSpec& specOf(MaterialKind kind);
const MaterialKindSpec* findMaterialKind(std::string_view name);  // nullptr: unknown
// "lambertian, principled, ...": the kinds a format accepts, for its error message.
std::string materialKindNames(bool (*accepted)(const MaterialKindSpec&));

// Every parameter of the material, "name value" pairs in the kind's order (kiln info).
std::string describeParams(const Material& m);

}  // namespace kiln
