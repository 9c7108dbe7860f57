#include "integrators/integrator.h"

#include "integrators/bsdf.h"
#include "renderer/geometry/interaction.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

Integrator::Integrator(const Scene& scene, const Accelerator& accel, const AovRequest& aovs,
                       float pixelSpread)
    : scene_(scene),
      accel_(accel),
      aovs_(aovs),
      pixelSpread_(pixelSpread),
      colourVaries_(hasSurfaceColourVariation(scene)),
      cameraForward_(normalize(scene.camera.forward)) {
    if (aovs.has(AovKind::CryptoObject) || aovs.has(AovKind::CryptoMaterial))
        cryptoIds_ = CryptoIds(scene);
}

void Integrator::recordSurface(const Ray& ray, const Hit& hit, const SurfaceInteraction& si,
                               SampleRecord& r) const {
    const Material& m = scene_.materials[si.material];
    if (aovs_.recordsAlbedo()) {
        Color base = colourVaries_
                         ? baseColourAt(scene_, m, hit, hit.t * length(ray.dir) * pixelSpread_)
                         : m.albedo;
        r.albedo = Bsdf::aovAlbedo(m, base);
    }
    r.normal = si.ns;
    r.position = Vec3(Vec3d(si.p) + scene_.origin);  // world coordinates
    r.hit = true;
    r.hitEmitter = maxComponent(m.emission) > 0;
    r.depth = hit.t * length(ray.dir);
    // Camera-space z: along the view axis from the lens plane (a thin lens's rays start on it).
    r.cameraZ = dot(ray.origin + ray.dir * hit.t - scene_.camera.position, cameraForward_);
    r.primId = float(hit.prim);
    r.objectId = float(hit.shape == kSphereShape ? scene_.meshes.size() + hit.prim : hit.shape);
    if (aovs_.has(AovKind::CryptoObject)) r.cryptoObject = cryptoIds_.object(hit);
    if (aovs_.has(AovKind::CryptoMaterial)) r.cryptoMaterial = cryptoIds_.material(si.material);
}

}  // namespace kiln
