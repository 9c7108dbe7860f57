#include "renderer/exr_scene.h"

#include <cmath>

#include "integrators/crypto_names.h"
#include "renderer/film/cryptomatte.h"
#include "renderer/geometry/camera.h"

namespace kiln {
namespace {

using Mat = std::array<double, 16>;  // row-major, row vectors: p' = p M

Mat multiply(const Mat& a, const Mat& b) {
    Mat m{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) m[4 * r + c] += a[4 * r + k] * b[4 * k + c];
    return m;
}

std::array<float, 16> toFloat(const Mat& m) {
    std::array<float, 16> f;
    for (int i = 0; i < 16; ++i) f[i] = float(m[i]);
    return f;
}

// NDC: x = 0.5 + 0.5 xc / (zc tan(hfov/2)), y = 0.5 - 0.5 yc / (zc tan(vfov/2)); w = zc.
Mat perspectiveNdc(const CameraModel& model) {
    double tx = std::tan(model.hFovDeg() * kPi / 360.0),
           ty = std::tan(model.vFovDeg() * kPi / 360.0);
    Mat project{};
    project[0 * 4 + 0] = 0.5 / tx;
    project[1 * 4 + 1] = -0.5 / ty;
    project[2 * 4 + 0] = 0.5, project[2 * 4 + 1] = 0.5, project[2 * 4 + 3] = 1;
    project[3 * 4 + 2] = 1;  // z' / w = 1 / zc: keeps the matrix invertible
    return project;
}

// Orthographic: x = 0.5 + 0.5 xc / half width, y = 0.5 - 0.5 yc / half height, z' = zc; w = 1.
Mat orthographicNdc(const CameraModel& model) {
    Mat project{};
    project[0 * 4 + 0] = 0.5 / model.orthoHalfWidth();
    project[1 * 4 + 1] = -0.5 / model.orthoHalfHeight();
    project[2 * 4 + 2] = 1;
    project[3 * 4 + 0] = 0.5, project[3 * 4 + 1] = 0.5, project[3 * 4 + 3] = 1;
    return project;
}

}  // namespace

ExrCamera exrCamera(const Scene& scene, const RenderSettings& settings) {
    CameraModel model(scene.camera, settings.width, settings.height);
    // The same basis CameraModel builds: right = forward x up, up' = right x forward.
    Vec3d f = Vec3d(normalize(scene.camera.forward));
    Vec3d r = cross(f, Vec3d(scene.camera.up));
    if (dot(r, r) < 1e-12) {  // up parallel to forward: CameraModel's choice
        Vec3 rf, t;
        orthonormalBasis(Vec3(f), rf, t);
        r = Vec3d(rf);
    }
    r = normalize(r);
    Vec3d u = cross(r, f);
    Vec3d eye = Vec3d(scene.camera.position) + scene.origin;
    // OpenEXR's camera space is left-handed: x right, y up, z along the view.
    Mat toCamera{};
    const Vec3d axes[3] = {r, u, f};
    for (int c = 0; c < 3; ++c) {
        toCamera[0 * 4 + c] = axes[c].x, toCamera[1 * 4 + c] = axes[c].y;
        toCamera[2 * 4 + c] = axes[c].z, toCamera[3 * 4 + c] = -dot(eye, axes[c]);
    }
    toCamera[15] = 1;
    Mat project = model.orthographic() ? orthographicNdc(model) : perspectiveNdc(model);
    return {toFloat(toCamera), toFloat(multiply(toCamera, project))};
}

void addSceneToExr(ExrOptions& options, const Scene& scene, const RenderSettings& settings,
                   const AovRequest& aovs) {
    options.camera = exrCamera(scene, settings);
    if (!aovs.has(AovKind::CryptoObject) && !aovs.has(AovKind::CryptoMaterial)) return;
    CryptoNames names(scene);
    if (aovs.has(AovKind::CryptoObject))
        options.cryptoManifests["CryptoObject"] = cryptoManifest(names.objects(scene));
    if (aovs.has(AovKind::CryptoMaterial))
        options.cryptoManifests["CryptoMaterial"] = cryptoManifest(names.materials);
}

}  // namespace kiln
