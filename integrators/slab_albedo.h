// The albedo inversion of subsurface scattering, derived rather than fitted: the diffuse albedo of
// a semi-infinite, isotropically scattering medium under the walk's own conventions (light enters
// cosine-distributed, the boundary is index-matched: a walk leaves wherever it reaches the
// surface), from Chandrasekhar's H-function (Radiative Transfer, 1950): R(omega) = 1 - 2
// sqrt(1 - omega) int_0^1 H(mu) mu dmu, and its inverse by a table made once per process.
#pragma once

namespace kiln {

// The zeroth and first moments of the H-function for isotropic scattering with single-scattering
// albedo omega in [0, 1), int_0^1 H(mu) mu^k dmu, by Gauss-Legendre quadrature of the H-equation
// (its cost grows as 1 / sqrt(1 - omega); within 1e-8 of 1, the limits at 1: 2 and 2 / sqrt(3)).
struct HMoments {
    double h0 = 0, h1 = 0;
};
HMoments hFunctionMoments(double omega);

// The fraction of light entering a semi-infinite medium cosine-distributed that comes back out
// (omega 1: all of it).
double slabAlbedo(double omega);

// The single-scattering albedo whose semi-infinite medium reflects `albedo` (clamped to [0, 1]):
// the inverse of slabAlbedo, monotone, interpolated in sqrt(1 - omega) from 257 exact values.
float singleScatteringAlbedoFor(float albedo);

}  // namespace kiln
