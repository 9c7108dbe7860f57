// The derived albedo inversion (integrators/slab_albedo.h): the H-function's moments against their
// closed forms, and the inverse table against the function it inverts. The walk through kiln's
// own code reflecting what the table promises is Subsurface.AlbedoInversionReflectsTheAlbedoFrom-
// ASemiInfiniteMedium.
#include <gtest/gtest.h>

#include <cmath>

#include "integrators/slab_albedo.h"

namespace kiln {
namespace {

// int_0^1 H dmu = 2 (1 - sqrt(1 - omega)) / omega exactly (the H-function's zeroth moment), and the
// first moment tends to 2 / sqrt(3) as omega tends to 1, linearly in sqrt(1 - omega).
TEST(SlabAlbedo, HFunctionMomentsMatchTheirClosedForms) {
    for (double omega : {0.05, 0.2, 0.5, 0.9, 0.99, 0.9999}) {
        double exact = 2 * (1 - std::sqrt(1 - omega)) / omega;
        EXPECT_NEAR(hFunctionMoments(omega).h0, exact, 1e-9) << "omega " << omega;
    }
    // Richardson extrapolation from sqrt(1 - omega) = 1/128 and 1/256 to 0: O(1/256^2) left.
    const double h1At128 = hFunctionMoments(1 - 1.0 / (128 * 128)).h1;
    const double h1At256 = hFunctionMoments(1 - 1.0 / (256 * 256)).h1;
    EXPECT_NEAR(2 * h1At256 - h1At128, 2 / std::sqrt(3.0), 1e-4);
    EXPECT_NEAR(hFunctionMoments(1).h1, 2 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(slabAlbedo(0), 0.0, 1e-12);  // H = 1: R = 1 - 2 (1/2)
    EXPECT_DOUBLE_EQ(slabAlbedo(1), 1.0);
}

// Albedos Chiang et al.'s fit gives for 0.9, 0.8, 0.7 and a one-off Monte Carlo of 400k walks
// (0.870, 0.796, 0.705; docs/light-transport.md) agree with the H-function's slab.
TEST(SlabAlbedo, AgreesWithAnIndependentMonteCarlo) {
    EXPECT_NEAR(slabAlbedo(0.99636), 0.870, 0.002);
    EXPECT_NEAR(slabAlbedo(0.99009), 0.796, 0.002);
    EXPECT_NEAR(slabAlbedo(0.97688), 0.705, 0.002);
}

TEST(SlabAlbedo, InversionIsMonotoneAndRoundTrips) {
    float previous = -1;
    for (int i = 0; i <= 1000; ++i) {
        float albedo = float(i) / 1000;
        float omega = singleScatteringAlbedoFor(albedo);
        EXPECT_GE(omega, previous) << "albedo " << albedo;
        previous = omega;
        EXPECT_NEAR(slabAlbedo(omega), albedo, 1e-4) << "albedo " << albedo;
    }
    EXPECT_EQ(singleScatteringAlbedoFor(1.0f), 1.0f);
    EXPECT_EQ(singleScatteringAlbedoFor(0.0f), 0.0f);
    EXPECT_EQ(singleScatteringAlbedoFor(2.0f), 1.0f);  // clamped
}

}  // namespace
}  // namespace kiln
