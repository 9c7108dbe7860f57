// The principled BSDF's transmission, sheen and specular-colour lobes: sampling agrees with the
// pdf over the whole sphere (chi-square, reflection and transmission together, from outside and
// from inside a volume), sample() agrees with eval() and pdf(), the white furnace (a white
// transmissive surface returns what arrives, less the single-scattering GGX loss; the sheen layer
// adds no energy), reciprocity (reflection and thin-walled transmission: f(wo, wi) = f(wi, wo);
// refraction: f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2), and the sheen albedo table against
// quadrature.
#include "bsdf_check.h"
#include "chi2.h"
#include "integrators/bsdf.h"
#include "principled_support.h"
#include "test_support.h"

namespace kiln::test {
namespace {

Material transmissive(float roughness, float thickness, Color base = Color(0.9f, 0.7f, 0.5f)) {
    Material m = principled(0, roughness, 0, 0, base);
    m.transmission = 1;
    m.thickness = thickness;
    return m;
}

Material sheened(float sheenRoughness, float roughness = 0.5f) {
    Material m = principled(0, roughness, 0, 0, Color(0.3f, 0.4f, 0.6f));
    m.sheen = 1;
    m.sheenColor = Color(1.0f, 0.8f, 0.6f);
    m.sheenRoughness = sheenRoughness;
    return m;
}

struct Setting {
    const char* name;
    Material material;
};

std::vector<Setting> settings() {
    Material half = transmissive(0.4f, 1);
    half.transmission = 0.5f;
    half.metallic = 0.2f;
    Material tinted = principled(0, 0.35f, 0, 0, Color(0.5f));
    tinted.specularColor = Color(1.0f, 0.3f, 0.1f);
    tinted.specular = 2.0f;
    Material all = sheened(0.6f, 0.3f);
    all.transmission = 0.7f;
    all.thickness = 1;
    all.clearcoat = 0.5f, all.clearcoatRoughness = 0.2f;
    // Refraction narrows the lobe by about (eta - 1) / eta: at normal incidence a rough-0.3
    // volume's transmission peaks within 2 degrees of the pole, where the chi-square's midpoint
    // integration of the expected counts errs by more than 1 % of 10^5 samples; rough 0.4 stays
    // resolvable.
    return {{"volume rough 0.4", transmissive(0.4f, 1)},
            {"volume rough 0.6 ior 1.33",
             [] {
                 Material m = transmissive(0.6f, 1);
                 m.ior = 1.33f;
                 return m;
             }()},
            {"thin rough 0.3", transmissive(0.3f, 0)},
            {"half transmissive", half},
            {"sheen rough 0.3", sheened(0.3f)},
            {"sheen rough 0.9", sheened(0.9f)},
            {"specular colour", tinted},
            {"every lobe", all}};
}

class PrincipledLobeSampling : public ::testing::TestWithParam<float> {};

TEST_P(PrincipledLobeSampling, ChiSquareOverTheSphereAndConsistency) {
    Vec3 wo = direction(GetParam());
    for (const Setting& c : settings()) {
        for (bool below : {false, true}) {  // outside; inside a volume (or the mirrored side)
            Vec3 w = below ? Vec3(wo.x, wo.y, -wo.z) : wo;
            Bsdf bsdf(c.material, MicrofacetModel::GGX);
            int inconsistent = 0, wrongSide = 0;
            auto sample = [&](Sampler& s) -> std::optional<Vec3> {
                BsdfSample bs;
                float uc = s.next1D(), u1 = s.next1D(), u2 = s.next1D();
                if (!bsdf.sample(w, uc, u1, u2, bs)) return std::nullopt;
                wrongSide += bs.delta || (bs.wi.z * w.z < 0) != bs.transmission;
                inconsistent += test::disagreesWithEvalAndPdf(bsdf, w, bs);
                return bs.wi;
            };
            test::Chi2Result r = test::chi2Directions(
                sample, [&](const Vec3& wi) { return bsdf.pdf(w, wi); }, 200000, 29, 80, 160, 8);
            EXPECT_GT(r.pValue, 1e-4)
                << c.name << " theta " << GetParam() << (below ? " below" : "") << ": " << r.table;
            EXPECT_EQ(inconsistent, 0) << c.name << (below ? " below" : "");
            EXPECT_EQ(wrongSide, 0) << c.name << (below ? " below" : "");
        }
    }
}

INSTANTIATE_TEST_SUITE_P(IncidentAngles, PrincipledLobeSampling,
                         ::testing::Values(0.0f, 40.0f, 75.0f));

// eval and pdf are finite everywhere, and pdf > 0 wherever eval is (else sampling would miss it).
TEST(PrincipledLobes, PdfCoversEval) {
    for (const Setting& c : settings()) {
        Bsdf bsdf(c.material, MicrofacetModel::GGX);
        for (float to : {0.0f, 30.0f, 70.0f, 89.0f, 110.0f, 160.0f})
            for (float ti = 0; ti <= 180; ti += 7.5f)
                for (float phi : {0.0f, 90.0f, 210.0f}) {
                    Vec3 wo = direction(to), wi = direction(ti, phi);
                    Color f = bsdf.eval(wo, wi);
                    float pdf = bsdf.pdf(wo, wi);
                    ASSERT_TRUE(isFinite(f) && std::isfinite(pdf)) << c.name;
                    if (maxComponent(f) > 0) {
                        EXPECT_GT(pdf, 0.0f) << c.name << " " << to << " " << ti;
                    }
                }
    }
}

// A white, non-absorbing transmissive surface: reflection and transmission (eta^2 times the
// radiance, what crosses as energy) return what arrives, less only what single-scattering GGX
// loses; smooth, nearly all of it. Seen from inside, total internal reflection keeps the rest.
TEST(PrincipledLobes, WhiteTransmissionFurnace) {
    for (float thickness : {0.0f, 1.0f})
        for (bool inside : {false, true})
            for (float roughness : {0.0f, 0.3f})
                for (float theta : {0.0f, 45.0f, 70.0f}) {
                    Material m = transmissive(roughness, thickness, Color(1.0f));
                    Vec3 wo = direction(theta);
                    if (inside) wo.z = -wo.z;
                    double eta2 = thickness > 0 ? m.ior * m.ior : 1.0;
                    if (inside) eta2 = 1 / eta2;
                    Albedo a =
                        directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), wo, 100000, 47, eta2);
                    std::string at = "thickness " + std::to_string(thickness) + " rough " +
                                     std::to_string(roughness) + " theta " + std::to_string(theta) +
                                     (inside ? " inside" : "");
                    EXPECT_LE(a.mean, 1.0 + 4.5 * a.stdError) << at;
                    // Smooth: a spike of GGX (alpha 1e-3) loses nothing; rough 0.3 at most a few %.
                    double loss = roughness == 0 ? 0.002 : 0.06;
                    EXPECT_GE(a.mean, 1.0 - loss - 4.5 * a.stdError) << at << ": " << a.mean;
                }
}

// Sheen over a white diffuse base adds no energy (its layer takes what it reflects from below).
TEST(PrincipledLobes, WhiteSheenFurnace) {
    for (float sheenRoughness : {0.1f, 0.5f, 1.0f})
        for (float theta : {0.0f, 60.0f, 85.0f}) {
            Material m = sheened(sheenRoughness, 1.0f);
            m.albedo = Color(1.0f), m.sheenColor = Color(1.0f);
            Albedo a =
                directionalAlbedo(Bsdf(m, MicrofacetModel::GGX), direction(theta), 100000, 53);
            EXPECT_LE(a.mean, 1.0 + 4.5 * a.stdError)
                << "sheen roughness " << sheenRoughness << " theta " << theta;
        }
}

// The sheen lobe's own albedo: at most about 1 (Estevez-Kulla's fitted Lambda gains a little at
// grazing angles), and the table (half-vector quadrature) agrees with a fine quadrature over wi,
// a second method, between its nodes (where interpolation errs most).
TEST(PrincipledLobes, SheenAlbedoTableMatchesQuadrature) {
    for (float r : {0.1f, 0.33f, 0.71f, 1.0f})
        for (float c : {0.05f, 0.3f, 0.62f, 0.97f}) {
            SheenLobe lobe(r);
            double exact = sheenAlbedoByQuadrature(lobe, c, 512);
            EXPECT_LE(exact, 1.03) << r << " " << c;
            EXPECT_NEAR(lobe.albedo(c), exact, 0.01 + 0.03 * exact)
                << "roughness " << r << " cos " << c;
        }
}

// Reflection, sheen and thin-walled transmission are reciprocal; refraction up to the indices
// (the radiance BTDF carries 1 / eta^2). The coat's weight is taken at wo alone, so not here.
TEST(PrincipledLobes, Reciprocity) {
    Material all = sheened(0.5f, 0.4f);
    all.transmission = 0.6f;
    Material thin = all;
    thin.thickness = 0;
    Material volume = all;
    volume.thickness = 1;
    for (const Material& m : {thin, volume}) {
        Bsdf bsdf(m, MicrofacetModel::GGX);
        for (float to : {10.0f, 40.0f, 80.0f, 130.0f, 170.0f})
            for (float ti : {5.0f, 35.0f, 60.0f, 100.0f, 150.0f, 175.0f}) {
                Vec3 a = direction(to, 20), b = direction(ti, 230);
                Color fab = bsdf.eval(a, b), fba = bsdf.eval(b, a);
                float scale = 1;
                if (m.thickness > 0 && a.z * b.z < 0)  // eta_b^2 / eta_a^2
                    scale = a.z > 0 ? m.ior * m.ior : 1 / (m.ior * m.ior);
                Color lhs = fab * scale;
                EXPECT_LE(maxComponent(abs(lhs - fba)), 1e-4f * maxComponent(fba) + 1e-7f)
                    << "thickness " << m.thickness << " " << to << " " << ti;
            }
    }
}

// KHR_materials_specular: the colour tints the dielectric's reflection per channel.
TEST(PrincipledLobes, SpecularColourTintsTheDielectricF0) {
    Material black = principled(0, 0.3f, 0, 0, Color(0.0f));
    black.specularColor = Color(1.0f, 0.5f, 0.25f);
    Vec3 n(0, 0, 1);
    Color f = Bsdf(black, MicrofacetModel::GGX).eval(n, n);
    EXPECT_NEAR(f.y / f.x, 0.5f, 1e-5f);
    EXPECT_NEAR(f.z / f.x, 0.25f, 1e-5f);
}

// Thin-walled, smooth, white: what passes goes straight on, undeviated; with thickness it bends.
TEST(PrincipledLobes, ThinWallsDoNotBendVolumesDo) {
    Vec3 wo = direction(50);
    for (float thickness : {0.0f, 1.0f}) {
        Bsdf bsdf(transmissive(0, thickness, Color(1.0f)), MicrofacetModel::GGX);
        BsdfSample bs;
        ASSERT_TRUE(bsdf.sample(wo, 0.999f, 0.3f, 0.6f, bs));
        ASSERT_TRUE(bs.transmission);
        float sinOut = std::sqrt(1 - bs.wi.z * bs.wi.z), sinIn = std::sqrt(1 - wo.z * wo.z);
        float expected = thickness > 0 ? sinIn / 1.5f : sinIn;
        EXPECT_NEAR(sinOut, expected, 0.01f) << "thickness " << thickness;
    }
}

}  // namespace
}  // namespace kiln::test
