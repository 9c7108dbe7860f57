// The sheen lobe of the principled material (KHR_materials_sheen): the "Charlie" distribution of
// Estevez and Kulla (2017) with their fitted Smith Lambda, as the glTF specification writes it, and
// its directional albedo E(cos) for the energy the sheen layer takes from the layers below it.
// Local frame, z = normal; alpha = sheen roughness^2.
#pragma once

#include "renderer/core/math.h"

namespace kiln {

class SheenLobe {
  public:
    // Perceptual roughness below this is a grazing spike float cannot integrate (glTF viewers
    // clamp as well).
    static constexpr float kMinRoughness = 0.07f;
    explicit SheenLobe(float roughness);

    // The Charlie distribution D(h) = (2 + 1 / alpha) sin(theta_h)^(1 / alpha) / (2 pi).
    float distribution(const Vec3& h) const;
    // D V of the lobe, white (times the sheen colour by the caller); wo and wi above the surface.
    float eval(const Vec3& wo, const Vec3& wi) const;
    // Its directional albedo from a direction at cosTheta above the surface (a table, once per
    // process, by quadrature of eval()).
    float albedo(float cosTheta) const;
    float roughness() const { return roughness_; }

  private:
    float lambda(float cosTheta) const;
    float roughness_ = 0.5f, alpha_ = 0.25f;
    float fitA_, fitB_, fitC_, fitD_, fitE_;  // Estevez-Kulla's fit, interpolated for alpha
    float fit(float x) const;
};

// The directional albedo by two quadratures: over wi (n x 2n nodes in cos^2 and phi: a check),
// and over half vectors in the measure D cos (what albedo() tabulates: flat where D peaks).
double sheenAlbedoByQuadrature(const SheenLobe& lobe, float cosTheta, int n);
double sheenAlbedoByHalfVectors(const SheenLobe& lobe, float cosTheta, int n);

}  // namespace kiln
