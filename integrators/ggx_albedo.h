// The directional albedo of the principled material's dielectric specular lobe (Schlick's F with
// F0, GGX D and height-correlated G2, single scattering), E(cos) = F0 E1(cos) + (1 - F0) Ew(cos),
// and its cosine-weighted mean over directions: what the diffuse lobe below it keeps, energy-
// conserving and reciprocal, as (1 - E(n.wo)) (1 - E(n.wi)) / (1 - E_avg) (Kulla and Conty 2017's
// albedo scaling; docs/light-transport.md). E1 and Ew are tables over the cosine and the perceptual
// roughness, made once per process by quadrature over half vectors.
#pragma once

namespace kiln {

float ggxDielectricAlbedo(float cosTheta, float roughness, float f0);
float ggxDielectricAlbedoAverage(float roughness, float f0);

// One entry by quadrature (what the tables hold): {E1, Ew} at the cosine and GGX alpha, with n x n
// nodes.
struct GgxAlbedoParts {
    double one = 0, schlick = 0;
};
GgxAlbedoParts ggxAlbedoByQuadrature(float cosTheta, float alpha, int n);

}  // namespace kiln
