#include "integrators/media.h"

#include "renderer/geometry/interaction.h"
#include "scene/material_kinds.h"

namespace kiln {
namespace {

// A shadow ray passes at most this many boundaries (a cloud of bubbles): beyond, it counts as
// blocked.
constexpr int kMaxCrossings = 64;

// Six times the volume a closed mesh encloses, positive when its winding normals point outwards.
double signedVolume6(const TriangleMesh& m) {
    double v = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        Vec3d a(m.vertex(m.indices[3 * t])), b(m.vertex(m.indices[3 * t + 1])),
            c(m.vertex(m.indices[3 * t + 2]));
        v += dot(a, cross(b, c));
    }
    return v;
}

}  // namespace

SceneMedia::SceneMedia(const Scene& scene) : scene_(scene) {
    for (const Medium& m : scene.media) media_.emplace_back(m);
    for (const TriangleMesh& m : scene.meshes) {
        interior_.push_back(m.interior);
        inward_.push_back(m.interior >= 0 && signedVolume6(m) < 0);
    }
    // A refracting surface bounds its medium itself (its BSDF bends the ray): a dielectric, or a
    // principled surface transmitting through a volume (thickness > 0; a thin wall does not bend
    // the ray). Any other surface with an interior is only where the medium starts.
    for (const Material& m : scene.materials) {
        const MaterialKindSpec& k = specOf(m.kind);
        const bool volume = k.transmits && k.transmits(m) && m.thickness > 0;
        dielectric_.push_back(k.transmission || volume);
    }
}

int SceneMedia::across(const SurfaceInteraction& si, int medium) const {
    Hit hit;
    hit.shape = si.shape, hit.instance = si.instance;
    return interiorOf(hit) >= 0 ? beyond(hit, si.frontFace) : medium;
}

Color SceneMedia::transmittance(const Accelerator& accel, const Ray& shadow, int medium,
                                uint64_t& rays) const {
    Color tr(1.0f);
    Ray ray = shadow;
    const bool toPoint = std::isfinite(shadow.tMax);
    const Vec3 end = toPoint ? shadow.origin + shadow.dir * shadow.tMax : Vec3(0.0f);
    for (int crossing = 0; crossing <= kMaxCrossings; ++crossing) {
        Hit hit;
        ++rays;
        const bool found = accel.intersect(ray, hit);
        if (medium >= 0)
            tr *=
                media_[size_t(medium)].transmittance((found ? hit.t : ray.tMax) * length(ray.dir));
        if (!found || maxComponent(tr) <= 0) return tr;
        SurfaceInteraction si = makeInteraction(scene_, ray, hit);
        if (!indexMatched(hit, si.material)) return Color(0.0f);
        medium = beyond(hit, si.frontFace);
        const Vec3 o = offsetRayOrigin(si, ray.dir);
        if (!toPoint) {
            ray = Ray{o, 0.0f, ray.dir, kInfinity};
        } else {
            if (dot(end - o, ray.dir) <= 0) return tr;  // the boundary lies at the end
            ray = Ray{o, 0.0f, end - o, 1.0f};
        }
    }
    return Color(0.0f);
}

}  // namespace kiln
