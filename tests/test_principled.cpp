// The principled BSDF: sampling agrees with the pdf (chi-square) for several metallic / roughness /
// clearcoat settings, sample() agrees with eval() and pdf(), and the white furnace: a white
// dielectric reflects at most what arrives, a white metal (F0 = 1) exactly the single-scattering
// GGX albedo (1 minus the energy GGX without multiple scattering loses).
#include "bsdf_check.h"
#include "chi2.h"
#include "integrators/bsdf.h"
#include "integrators/ggx_albedo.h"
#include "principled_support.h"
#include "test_support.h"

namespace kiln {
namespace {

using test::Albedo;
using test::direction;
using test::directionalAlbedo;
using test::principled;

struct Setting {
    const char* name;
    Material material;
};

std::vector<Setting> settings() {
    return {{"dielectric rough 0.6", principled(0, 0.6f)},
            {"dielectric rough 0.25", principled(0, 0.25f)},
            {"metal rough 0.3", principled(1, 0.3f)},
            {"half metal rough 0.45", principled(0.5f, 0.45f)},
            {"coated dielectric", principled(0, 0.8f, 1, 0.2f)},
            {"coated metal", principled(1, 0.5f, 0.5f, 0.3f)},
            {"black metal", principled(1, 0.4f, 0, 0, Color(0.0f))}};
}

class PrincipledSampling : public ::testing::TestWithParam<float> {};

TEST_P(PrincipledSampling, ChiSquareAndConsistency) {
    Vec3 wo = direction(GetParam());
    for (const Setting& c : settings()) {
        for (bool below : {false, true}) {  // opaque and two-sided
            Vec3 w = below ? Vec3(wo.x, wo.y, -wo.z) : wo;
            Bsdf bsdf(c.material, MicrofacetModel::GGX);
            int inconsistent = 0;
            auto sample = [&](Sampler& s) -> std::optional<Vec3> {
                BsdfSample bs;
                float uc = s.next1D(), u1 = s.next1D(), u2 = s.next1D();
                if (!bsdf.sample(w, uc, u1, u2, bs)) return std::nullopt;
                if (bs.delta || bs.transmission || bs.wi.z * w.z <= 0 ||
                    test::disagreesWithEvalAndPdf(bsdf, w, bs))
                    ++inconsistent;
                return bs.wi;
            };
            test::Chi2Result r = test::chi2Directions(
                sample, [&](const Vec3& wi) { return bsdf.pdf(w, wi); }, 200000, 23, 80, 160, 8);
            EXPECT_GT(r.pValue, 1e-4)
                << c.name << " theta " << GetParam() << (below ? " below" : "") << ": " << r.table;
            EXPECT_EQ(inconsistent, 0) << c.name;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(IncidentAngles, PrincipledSampling, ::testing::Values(0.0f, 45.0f, 80.0f));

// eval and pdf vanish together off the reflecting hemisphere, and pdf > 0 wherever eval is.
TEST(PrincipledBsdf, EvalAndPdfAgreeOnSupport) {
    for (const Setting& c : settings()) {
        Bsdf bsdf(c.material, MicrofacetModel::GGX);
        for (float to : {0.0f, 30.0f, 70.0f, 89.0f})
            for (float ti = 0; ti < 180; ti += 7.5f)
                for (float phi : {0.0f, 90.0f, 210.0f}) {
                    Vec3 wo = direction(to), wi = direction(ti, phi);
                    Color f = bsdf.eval(wo, wi);
                    float pdf = bsdf.pdf(wo, wi);
                    ASSERT_TRUE(isFinite(f) && std::isfinite(pdf)) << c.name;
                    if (wi.z <= 0) {
                        EXPECT_EQ(maxComponent(f), 0.0f) << c.name;
                        EXPECT_EQ(pdf, 0.0f) << c.name;
                    } else if (maxComponent(f) > 0) {
                        EXPECT_GT(pdf, 0.0f) << c.name << " " << to << " " << ti;
                    }
                }
    }
}

// A white dielectric reflects what arrives: the diffuse lobe keeps exactly what the specular lobe
// leaves (integrators/ggx_albedo.h); a coat over it takes its share and adds at most that.
TEST(PrincipledFurnace, WhiteDielectricReflectsAtMostWhatArrives) {
    // The albedo tables' own error (SpecularAlbedoTableMatchesQuadrature: 0.002 + 1 % of E,
    // E < 0.5 here) enters the diffuse weight once.
    constexpr double kTableError = 0.007;
    for (float roughness : {0.1f, 0.5f, 1.0f})
        for (float clearcoat : {0.0f, 1.0f})
            for (float theta : {0.0f, 45.0f, 75.0f, 88.0f}) {
                Material m = principled(0, roughness, clearcoat, 0.3f, Color(1.0f));
                Albedo a =
                    directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), direction(theta), 200000, 41);
                // A 4.5 sigma bound on the estimator (its variance from the samples).
                std::string at = "roughness " + std::to_string(roughness) + " clearcoat " +
                                 std::to_string(clearcoat) + " theta " + std::to_string(theta) +
                                 ": " + std::to_string(a.mean) + " +- " +
                                 std::to_string(a.stdError);
                EXPECT_LE(a.mean, 1.0 + 4.5 * a.stdError + kTableError) << at;
                if (clearcoat == 0) {
                    EXPECT_GE(a.mean, 1.0 - 4.5 * a.stdError - kTableError) << at;
                }
            }
}

TEST(PrincipledFurnace, WhiteMetalLosesOnlyWhatSingleScatteringGgxLoses) {
    double previousLoss = -1;
    for (float roughness : {0.1f, 0.4f, 0.7f, 1.0f}) {
        for (float theta : {0.0f, 60.0f, 85.0f}) {
            Material m = principled(1, roughness, 0, 0, Color(1.0f));
            Vec3 wo = direction(theta);
            Albedo a = directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), wo, 200000, 43);
            // The white conductor's single-scattering albedo by deterministic quadrature over half
            // vectors (integrators/ggx_albedo.h), independent of the BSDF's sampler.
            double expected = ggxAlbedoByQuadrature(wo.z, roughness * roughness, 1000).one;
            // 5 sigma of the estimator, plus the quadrature's own error (well below 1e-3 here).
            EXPECT_NEAR(a.mean, expected, 5 * a.stdError + 1e-3)
                << "roughness " << roughness << " theta " << theta;
            EXPECT_LE(expected, 1.0 + 1e-3);
            if (theta == 0) {
                // Single scattering loses more energy the rougher the surface, and nearly none
                // when it is smooth.
                double loss = 1 - expected;
                EXPECT_GT(loss, previousLoss) << "roughness " << roughness;
                if (roughness == 0.1f) {
                    EXPECT_LT(loss, 0.01);
                }
                previousLoss = loss;
            }
        }
    }
}

// F0 of the dielectric: 0.04 at ior 1.5 (Schlick at the half vector), scaled by `specular`.
TEST(PrincipledBsdf, DielectricSpecularIsFourPercentAtNormalIncidence) {
    Material black = principled(0, 0.3f, 0, 0, Color(0.0f));
    Material white = principled(1, 0.3f, 0, 0, Color(1.0f));
    Vec3 n(0, 0, 1);
    float ratio = Bsdf(black, MicrofacetModel::GGX).eval(n, n).x /
                  Bsdf(white, MicrofacetModel::GGX).eval(n, n).x;
    EXPECT_NEAR(ratio, 0.04f, 1e-5f);
    black.specular = 0.5f;
    ratio = Bsdf(black, MicrofacetModel::GGX).eval(n, n).x /
            Bsdf(white, MicrofacetModel::GGX).eval(n, n).x;
    EXPECT_NEAR(ratio, 0.02f, 1e-5f);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// The dielectric specular albedo tables behind the diffuse weight agree with a fine quadrature
// between their nodes, grazing angles included; the average is 2 int E mu dmu.
TEST(PrincipledFurnace, SpecularAlbedoTableMatchesQuadrature) {
    for (float r : {0.1f, 0.37f, 0.8f})
        for (float c : {0.035f, 0.2f, 0.6f, 0.95f}) {
            GgxAlbedoParts exact = ggxAlbedoByQuadrature(c, std::max(1e-3f, r * r), 400);
            double e = 0.04 * exact.one + 0.96 * exact.schlick;
            EXPECT_NEAR(ggxDielectricAlbedo(c, r, 0.04f), e, 0.002 + 0.01 * e)
                << "roughness " << r << " cos " << c;
        }
}

}  // namespace
}  // namespace kiln
