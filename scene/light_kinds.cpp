#include "scene/light_kinds.h"

#include <array>

namespace kiln {
namespace {

// Indexed by LightKind: name, delta, infinite, surface.
constexpr std::array<LightKindSpec, 7> kLightKinds = {{
    {LightKind::Area, "area", false, false, true},
    {LightKind::MeshEmitter, "emissive_mesh", false, false, true},
    {LightKind::Point, "point", true, false, false},
    {LightKind::Spot, "spot", true, false, false},
    {LightKind::Directional, "directional", true, false, false},
    {LightKind::Ambient, "ambient", false, true, false},
    {LightKind::Environment, "environment", false, true, false},
}};

static_assert(
    [] {
        for (size_t i = 0; i < kLightKinds.size(); ++i)
            if (size_t(kLightKinds[i].kind) != i) return false;
        return true;
    }(),
    "light_kinds: rows out of LightKind order");

}  // namespace

std::span<const LightKindSpec> lightKinds() { return kLightKinds; }
const LightKindSpec& specOf(LightKind kind) { return kLightKinds.at(size_t(kind)); }
const char* toString(LightKind kind) { return specOf(kind).name; }

}  // namespace kiln
