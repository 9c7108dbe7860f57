// The principled BSDF: sampling agrees with the pdf (chi-square) for several metallic / roughness /
// clearcoat settings, sample() agrees with eval() and pdf(), and the white furnace: a white
// dielectric reflects at most what arrives, a white metal (F0 = 1) exactly the single-scattering
// GGX albedo (1 minus the energy GGX without multiple scattering loses).
#include "bsdf_check.h"
#include "chi2.h"
#include "integrators/bsdf.h"
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

// The single-scattering albedo of a white (F = 1) GGX conductor by deterministic quadrature over
// half vectors, independent of the BSDF's sampler: with tan^2(theta_h) = alpha^2 u / (1 - u) the
// measure D(h) cos(theta_h) dw_h is du dphi / (2 pi), and wi = reflect(wo, h) carries
// G2 (wo.h) / (wo.z h.z).
double ggxAlbedoByQuadrature(float alpha, const Vec3& wo) {
    Microfacet m;
    m.model = MicrofacetModel::GGX;
    m.alpha = alpha;
    constexpr int kU = 4000, kPhi = 512;
    double sum = 0;
    for (int a = 0; a < kU; ++a) {
        double u = (a + 0.5) / kU;
        double tan2 = double(alpha) * alpha * u / (1 - u);
        double cosT = 1 / std::sqrt(1 + tan2), sinT = std::sqrt(1 - cosT * cosT);
        for (int b = 0; b < kPhi; ++b) {
            double phi = 2 * M_PI * (b + 0.5) / kPhi;
            Vec3 h(float(sinT * std::cos(phi)), float(sinT * std::sin(phi)), float(cosT));
            double d = dot(wo, h);
            if (d <= 0) continue;
            Vec3 wi = h * float(2 * d) - wo;
            if (wi.z <= 0) continue;
            sum += m.G(wo, wi) * d / (wo.z * cosT);
        }
    }
    return sum / (double(kU) * kPhi);
}

TEST(PrincipledFurnace, WhiteDielectricReflectsAtMostWhatArrives) {
    for (float roughness : {0.1f, 0.5f, 1.0f})
        for (float clearcoat : {0.0f, 1.0f})
            for (float theta : {0.0f, 45.0f, 75.0f, 88.0f}) {
                Material m = principled(0, roughness, clearcoat, 0.3f, Color(1.0f));
                Albedo a =
                    directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), direction(theta), 200000, 41);
                // A 4.5 sigma one-sided bound on the estimator (its variance from the samples).
                EXPECT_LE(a.mean, 1.0 + 4.5 * a.stdError)
                    << "roughness " << roughness << " clearcoat " << clearcoat << " theta " << theta
                    << ": " << a.mean << " +- " << a.stdError;
            }
}

TEST(PrincipledFurnace, WhiteMetalLosesOnlyWhatSingleScatteringGgxLoses) {
    double previousLoss = -1;
    for (float roughness : {0.1f, 0.4f, 0.7f, 1.0f}) {
        for (float theta : {0.0f, 60.0f, 85.0f}) {
            Material m = principled(1, roughness, 0, 0, Color(1.0f));
            Vec3 wo = direction(theta);
            Albedo a = directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), wo, 200000, 43);
            double expected = ggxAlbedoByQuadrature(roughness * roughness, wo);
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
