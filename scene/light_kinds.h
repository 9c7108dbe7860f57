// One description per light kind: its name (kiln info, EXR, .kiln kind=) and what the render plan
// and the integrators learn from it. The emitter itself (sampling, pdf, radiance) is LightSet's
// (integrators/lights.h), one case per kind.
#pragma once

#include <span>

#include "scene/scene.h"

namespace kiln {

struct LightKindSpec {
    LightKind kind;
    const char* name;
    bool delta = false;     // a point, direction or cone: only light sampling finds it
    bool infinite = false;  // at infinity: rays leaving the scene see it
    bool surface = false;   // emits from a surface of the scene (photons leave it)
    // A ray can hit this light (so BSDF sampling can find it and MIS weighs both ways).
    bool hittable(const Light& l) const {
        return infinite || kind == LightKind::MeshEmitter || (kind == LightKind::Area && l.hasMesh);
    }
};

std::span<const LightKindSpec> lightKinds();
const LightKindSpec& specOf(LightKind kind);

}  // namespace kiln
