// BSDFs: sampling agrees with the pdf (chi-square), sample() agrees with eval()/pdf(), energy
// bounds, and the delta lobes' directions and Fresnel-weighted choices.
#include "bsdf_check.h"
#include "chi2.h"
#include "integrators/bsdf.h"
#include "integrators/fresnel.h"
#include "test_support.h"

namespace kiln {
namespace {

Vec3 direction(float thetaDeg, float phiDeg = 30) {
    float t = radians(thetaDeg), p = radians(phiDeg);
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

struct BsdfCase {
    std::string name;
    Material material;
    MicrofacetModel model = MicrofacetModel::Beckmann;
};

std::vector<BsdfCase> bsdfCases() {
    std::vector<BsdfCase> cases;
    Material lambert;
    lambert.albedo = Color(0.8f, 0.5f, 0.2f);
    cases.push_back({"lambert", lambert});
    for (float alpha : {0.05f, 0.25f, 0.6f}) {
        Material metal;
        metal.kind = MaterialKind::Microfacet;
        metal.alpha = alpha;
        metal.eta = Color(0.33228f, 1.0162f, 1.2474f);  // CBbunny_microfacet_cu
        metal.k = Color(3.1646f, 2.5785f, 2.4603f);
        cases.push_back({"beckmann_" + std::to_string(alpha), metal});
        cases.push_back({"ggx_" + std::to_string(alpha), metal, MicrofacetModel::GGX});
    }
    for (float n : {5.0f, 50.0f}) {
        Material glossy;
        glossy.kind = MaterialKind::Glossy;
        glossy.shininess = n;
        glossy.reflectance = Color(0.9f);
        cases.push_back({"glossy_" + std::to_string(int(n)), glossy});
    }
    return cases;
}

class BsdfSampling : public ::testing::TestWithParam<float> {};

TEST_P(BsdfSampling, ChiSquareAndConsistency) {
    Vec3 wo = direction(GetParam());
    for (const BsdfCase& c : bsdfCases()) {
        for (bool below : {false, true}) {  // opaque BSDFs are two-sided
            Vec3 w = below ? Vec3(wo.x, wo.y, -wo.z) : wo;
            Bsdf bsdf(c.material, c.model);
            int inconsistent = 0;
            auto sample = [&](Sampler& s) -> std::optional<Vec3> {
                BsdfSample bs;
                float uc = s.next1D(), u1 = s.next1D(), u2 = s.next1D();
                if (!bsdf.sample(w, uc, u1, u2, bs)) return std::nullopt;
                if (test::disagreesWithEvalAndPdf(bsdf, w, bs)) ++inconsistent;
                return bs.wi;
            };
            test::Chi2Result r = test::chi2Directions(
                sample, [&](const Vec3& wi) { return bsdf.pdf(w, wi); }, 400000, 17);
            EXPECT_GT(r.pValue, 1e-4)
                << c.name << " theta " << GetParam() << (below ? " below" : "") << ": " << r.table;
            EXPECT_EQ(inconsistent, 0) << c.name;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(IncidentAngles, BsdfSampling,
                         ::testing::Values(0.0f, 30.0f, 60.0f, 85.0f));

TEST(BsdfEnergy, ReflectedFractionNeverExceedsOne) {
    // Albedo estimated by sampling: the mean of f cos / pdf is at most 1 (0.8 for the Lambert
    // case).
    for (const BsdfCase& c : bsdfCases()) {
        Bsdf bsdf(c.material, c.model);
        for (float theta : {0.0f, 45.0f, 80.0f}) {
            Vec3 wo = direction(theta);
            double sum = 0;
            constexpr int kN = 100000;
            for (int i = 0; i < kN; ++i) {
                Sampler s(5, uint64_t(i), 0);
                BsdfSample bs;
                float uc = s.next1D(), u1 = s.next1D(), u2 = s.next1D();
                if (bsdf.sample(wo, uc, u1, u2, bs))
                    sum += maxComponent(bs.f) * std::abs(bs.wi.z) / bs.pdf;
            }
            EXPECT_LT(sum / kN, 1.02) << c.name << " theta " << theta;
            if (c.name == "lambert") {
                EXPECT_NEAR(sum / kN, 0.8, 0.01);
            }
        }
    }
}

TEST(DeltaBsdfs, MirrorReflectsWithItsReflectance) {
    Material m;
    m.kind = MaterialKind::Mirror;
    m.reflectance = Color(1.0f, 0.8f, 0.4f);
    Bsdf bsdf(m);
    Vec3 wo = direction(40);
    BsdfSample bs;
    ASSERT_TRUE(bsdf.sample(wo, 0.3f, 0.1f, 0.2f, bs));
    EXPECT_TRUE(bs.delta);
    EXPECT_NEAR(bs.wi.x, -wo.x, 1e-6f);
    EXPECT_NEAR(bs.wi.z, wo.z, 1e-6f);
    Color weight = bs.f * (std::abs(bs.wi.z) / bs.pdf);
    EXPECT_NEAR(weight.y, 0.8f, 1e-6f);
    EXPECT_EQ(bsdf.eval(wo, bs.wi), Color(0.0f));  // a delta lobe has no value off its direction
}

TEST(DeltaBsdfs, GlassChoosesReflectionWithFresnelProbabilityAndObeysSnell) {
    Material glass;
    glass.kind = MaterialKind::Glass;
    glass.ior = 1.45f;
    Bsdf bsdf(glass);
    for (float theta : {0.0f, 30.0f, 60.0f, 80.0f}) {
        for (bool inside : {false, true}) {
            Vec3 wo = direction(theta);
            if (inside) wo.z = -wo.z;
            float F = fresnelDielectric(wo.z, 1.45f);
            int reflections = 0;
            constexpr int kN = 200000;
            for (int i = 0; i < kN; ++i) {
                Sampler s(9, uint64_t(i), 0);
                BsdfSample bs;
                ASSERT_TRUE(bsdf.sample(wo, s.next1D(), s.next1D(), s.next1D(), bs));
                if (!bs.transmission) {
                    ++reflections;
                    continue;
                }
                // Snell: n_i sin_i = n_t sin_t, on the other side.
                float ni = inside ? 1.45f : 1.0f, nt = inside ? 1.0f : 1.45f;
                float sinI = std::sqrt(1 - wo.z * wo.z), sinT = std::sqrt(1 - bs.wi.z * bs.wi.z);
                ASSERT_NEAR(ni * sinI, nt * sinT, 1e-5f);
                ASSERT_LT(bs.wi.z * wo.z, 0.0f);
                // Weight: transmittance / eta^2 (radiance compression), whatever the lobe
                // probability.
                float eta = nt / ni;
                ASSERT_NEAR((bs.f * (std::abs(bs.wi.z) / bs.pdf)).x, 1 / (eta * eta), 1e-4f);
            }
            // Binomial: reflections ~ N F, standard deviation sqrt(N F (1 - F)); 5 sigma bound.
            double sigma = std::sqrt(kN * F * (1 - F));
            EXPECT_NEAR(reflections, kN * F, 5 * sigma + 1)
                << "theta " << theta << (inside ? " inside" : "");
        }
    }
    // Beyond the critical angle (inside, 60 degrees for n = 1.45): total internal reflection.
    Vec3 wo = direction(60);
    wo.z = -wo.z;
    BsdfSample bs;
    ASSERT_TRUE(bsdf.sample(wo, 0.99f, 0.5f, 0.5f, bs));
    EXPECT_FALSE(bs.transmission);
    EXPECT_FLOAT_EQ(bs.pdf, 1.0f);
}

TEST(DeltaBsdfs, RefractionOnlyAlwaysTransmits) {
    Material m;
    m.kind = MaterialKind::Refraction;
    m.ior = 1.45f;
    Bsdf bsdf(m);
    BsdfSample bs;
    ASSERT_TRUE(bsdf.sample(direction(45), 0.01f, 0.5f, 0.5f, bs));
    EXPECT_TRUE(bs.transmission);
    EXPECT_FLOAT_EQ(bs.pdf, 1.0f);
}

TEST(Fresnel, KnownValues) {
    // Normal incidence: ((n-1)/(n+1))^2.
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(-1.0f, 1.5f), 0.04f, 1e-6f);
    EXPECT_FLOAT_EQ(fresnelDielectric(0.0f, 1.5f), 1.0f);  // grazing
    // Conductor at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
    float n = 0.33228f, k = 3.1646f;
    EXPECT_NEAR(fresnelConductor1(1.0f, n, k),
                ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-5f);
    EXPECT_NEAR(fresnelConductor1(0.0f, n, k), 1.0f, 1e-5f);
}

}  // namespace
}  // namespace kiln
