// Fresnel equations against closed-form values, and the delta BSDFs built on them.
#include <gtest/gtest.h>

#include <cmath>

#include "support/bsdf_helpers.h"
#include "volguide/render/bsdfs/fresnel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Textbook unpolarized Fresnel reflectance, in double precision, n = n_t / n_i.
double fresnel_reference(double cos_i, double n) {
    if (cos_i < 0) {
        cos_i = -cos_i;
        n = 1.0 / n;
    }
    double sin_t2 = (1 - cos_i * cos_i) / (n * n);
    if (sin_t2 >= 1) return 1.0;
    double cos_t = std::sqrt(1 - sin_t2);
    double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace

TEST(Fresnel, NormalIncidence) {
    EXPECT_NEAR(fresnel_dielectric(1.f, 1.5f).F, 0.04f, 1e-6f);
    EXPECT_NEAR(fresnel_dielectric(-1.f, 1.5f).F, 0.04f, 1e-6f);
    EXPECT_NEAR(fresnel_dielectric(1.f, 1.333f).F, std::pow(0.333 / 2.333, 2), 1e-6);
}

TEST(Fresnel, MatchesClosedFormOverAngles) {
    for (float eta : {1.5f, 1.333f, 2.419f, 0.7f})
        for (int i = -20; i <= 20; ++i) {
            float c = i / 20.f;
            if (c == 0.f) continue;
            EXPECT_NEAR(fresnel_dielectric(c, eta).F, fresnel_reference(c, eta), 2e-6)
                << "eta " << eta << " cos " << c;
        }
}

TEST(Fresnel, BrewsterAndTotalInternalReflection) {
    // At Brewster's angle the p-polarised reflection vanishes: F = rs^2 / 2.
    const double n = 1.5, theta_b = std::atan(n);
    const double ci = std::cos(theta_b), ct = std::sqrt(1 - std::pow(std::sin(theta_b) / n, 2));
    const double rs = (ci - n * ct) / (ci + n * ct);
    EXPECT_NEAR(fresnel_dielectric(float(ci), 1.5f).F, 0.5 * rs * rs, 1e-6);
    // Inside, beyond the critical angle (sin > 1/1.5): total internal reflection.
    FresnelResult tir = fresnel_dielectric(-0.5f, 1.5f);
    EXPECT_EQ(tir.F, 1.f);
    EXPECT_EQ(fresnel_dielectric(0.3f, 1.f).F, 0.f);  // index matched
}

TEST(Fresnel, RefractionObeysSnell) {
    for (float c : {0.9f, 0.4f, -0.95f, -0.8f}) {
        Vec3f wi = dir(c, 0.7f);
        FresnelResult fr = fresnel_dielectric(wi.z, 1.5f);
        Vec3f wt = refract_local(wi, fr.cos_theta_t, fr.eta_ti);
        EXPECT_NEAR(norm(wt), 1.f, 1e-5f);
        EXPECT_LT(wt.z * wi.z, 0.f);
        float n_i = c > 0 ? 1.f : 1.5f, n_t = c > 0 ? 1.5f : 1.f;
        EXPECT_NEAR(n_i * Frame::sin_theta(wi), n_t * Frame::sin_theta(wt), 1e-5f);
        EXPECT_NEAR(fr.eta_it, n_t / n_i, 1e-6f);
    }
}

TEST(Fresnel, ConductorLimits) {
    // k = 0 reduces to a dielectric seen from outside.
    for (float c : {1.f, 0.7f, 0.2f})
        EXPECT_NEAR(fresnel_conductor(c, 1.5f, 0.f), fresnel_reference(c, 1.5), 1e-5);
    // Normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
    EXPECT_NEAR(fresnel_conductor(1.f, 0.2f, 3.9f), (0.64 + 3.9 * 3.9) / (1.44 + 3.9 * 3.9), 1e-5);
    // Mitsuba's "none" material (eta 0, k 1) is a perfect mirror at every angle.
    for (float c : {1.f, 0.5f, 0.05f}) EXPECT_NEAR(fresnel_conductor(c, 0.f, 1.f), 1.f, 1e-6f);
}

TEST(Fresnel, DiffuseReflectanceMatchesIntegral) {
    // Fdr = 2 * integral of F(cos) cos dcos over the hemisphere; Mitsuba's fits are within 1%.
    for (float eta : {1.33f, 1.5f, 1.8f, 1.f / 1.5f, 1.f / 1.33f}) {
        double sum = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
            double c = (i + 0.5) / n;
            sum += fresnel_reference(c, eta) * c;
        }
        double fdr = 2 * sum / n;
        EXPECT_NEAR(fresnel_diffuse_reflectance(eta), fdr, 0.01 * fdr) << "eta " << eta;
    }
}

TEST(DielectricBsdf, SampleWeightsAndDirections) {
    auto bsdf = make_bsdf("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    EXPECT_TRUE(bsdf->has(bsdf_flags::DeltaReflection));
    EXPECT_TRUE(bsdf->has(bsdf_flags::DeltaTransmission));
    SurfaceInteraction si = local_si(dir(0.8f));
    BSDFContext ctx;
    const float F = fresnel_dielectric(si.wi.z, 1.5f).F;
    // Reflection when sample1 <= F.
    auto [r, wr] = bsdf->sample(ctx, si, 0.5f * F, {0.5f, 0.5f});
    EXPECT_EQ(r.sampled_flags, uint32_t(bsdf_flags::DeltaReflection));
    EXPECT_NEAR(r.pdf, F, 1e-6f);
    EXPECT_NEAR(r.wo.z, si.wi.z, 1e-6f);
    EXPECT_NEAR(r.wo.x, -si.wi.x, 1e-6f);
    EXPECT_EQ(wr, Color3(1.f));
    // Transmission: radiance is scaled by 1 / eta^2 entering, importance is not.
    auto [t, wt] = bsdf->sample(ctx, si, 0.99f, {0.5f, 0.5f});
    EXPECT_EQ(t.sampled_flags, uint32_t(bsdf_flags::DeltaTransmission));
    EXPECT_NEAR(t.pdf, 1.f - F, 1e-6f);
    EXPECT_NEAR(t.eta, 1.5f, 1e-6f);
    EXPECT_NEAR(wt.r, 1.f / (1.5f * 1.5f), 1e-6f);
    ctx.mode = TransportMode::Importance;
    EXPECT_NEAR(bsdf->sample(ctx, si, 0.99f, {0.5f, 0.5f}).second.r, 1.f, 1e-6f);
    // Leaving the glass the radiance gains eta^2.
    ctx.mode = TransportMode::Radiance;
    SurfaceInteraction inside = local_si(dir(-0.95f));
    auto [t2, wt2] = bsdf->sample(ctx, inside, 0.999f, {0.5f, 0.5f});
    EXPECT_GT(t2.wo.z, 0.f);
    EXPECT_NEAR(t2.eta, 1.f / 1.5f, 1e-6f);
    EXPECT_NEAR(wt2.g, 1.5f * 1.5f, 1e-5f);
    // Delta BSDF: eval and pdf are zero.
    EXPECT_TRUE(bsdf->eval(ctx, si, t.wo).is_black());
    EXPECT_EQ(bsdf->pdf(ctx, si, t.wo), 0.f);
}

TEST(DielectricBsdf, SpecularModulation) {
    auto bsdf = make_bsdf("dielectric", {{"specular_reflectance", Color3(0.5f, 0.25f, 1.f)},
                                         {"specular_transmittance", Color3(0.2f)}});
    SurfaceInteraction si = local_si(dir(0.6f));
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    EXPECT_EQ(bsdf->sample(ctx, si, 0.f, {0.f, 0.f}).second, Color3(0.5f, 0.25f, 1.f));
    EXPECT_EQ(bsdf->sample(ctx, si, 0.9999f, {0.f, 0.f}).second, Color3(0.2f));
}

TEST(ThinDielectricBsdf, InterreflectionSum) {
    auto bsdf = make_bsdf("thindielectric", {{"int_ior", "bk7"}});
    SurfaceInteraction si = local_si(dir(-0.7f));
    const float R = fresnel_dielectric(0.7f, 1.5046f / 1.000277f).F, Rp = 2 * R / (1 + R);
    BSDFContext ctx;
    auto [r, wr] = bsdf->sample(ctx, si, 0.5f * Rp, {0.f, 0.f});
    EXPECT_EQ(r.sampled_flags, uint32_t(bsdf_flags::DeltaReflection));
    EXPECT_NEAR(r.pdf, Rp, 1e-6f);
    EXPECT_NEAR(r.wo.z, si.wi.z, 1e-6f);
    auto [t, wt] = bsdf->sample(ctx, si, 0.9f, {0.f, 0.f});
    EXPECT_EQ(t.sampled_flags, uint32_t(bsdf_flags::Null));
    EXPECT_NEAR(t.pdf, 1 - Rp, 1e-6f);
    EXPECT_EQ(t.wo, -si.wi);  // passes straight through
    EXPECT_EQ(wt, Color3(1.f));
    EXPECT_NEAR(bsdf->eval_null_transmission(si).r, 1 - Rp, 1e-6f);
}

TEST(NullBsdf, PassThrough) {
    auto bsdf = make_bsdf("null");
    EXPECT_TRUE(bsdf->is_null());
    SurfaceInteraction si = local_si(dir(0.3f));
    BSDFContext ctx;
    auto [bs, w] = bsdf->sample(ctx, si, 0.7f, {0.2f, 0.9f});
    EXPECT_EQ(bs.wo, -si.wi);
    EXPECT_EQ(bs.pdf, 1.f);
    EXPECT_EQ(bs.eta, 1.f);
    EXPECT_EQ(bs.sampled_flags, uint32_t(bsdf_flags::Null));
    EXPECT_EQ(w, Color3(1.f));
    EXPECT_TRUE(bsdf->eval(ctx, si, -si.wi).is_black());
    EXPECT_EQ(bsdf->pdf(ctx, si, -si.wi), 0.f);
    EXPECT_EQ(bsdf->eval_null_transmission(si), Color3(1.f));
    EXPECT_EQ(make_bsdf("diffuse")->eval_null_transmission(si), Color3(0.f));
}

TEST(ConductorBsdf, PresetsAndMirror) {
    BSDFContext ctx;
    SurfaceInteraction si = local_si(dir(0.6f));
    // Default material "none": a perfect mirror.
    auto mirror = make_bsdf("conductor");
    auto [bs, w] = mirror->sample(ctx, si, 0.3f, {0.1f, 0.2f});
    EXPECT_EQ(bs.sampled_flags, uint32_t(bsdf_flags::DeltaReflection));
    EXPECT_NEAR(w.r, 1.f, 1e-6f);
    EXPECT_NEAR(w.b, 1.f, 1e-6f);
    // Copper reflects red more than blue; weight = Fresnel at the incidence angle.
    auto cu = make_bsdf("conductor", {{"material", "Cu"}, {"specular_reflectance", Color3(0.5f)}});
    Color3 wc = cu->sample(ctx, si, 0.3f, {0.1f, 0.2f}).second;
    EXPECT_GT(wc.r, wc.b);
    EXPECT_NEAR(wc.r, 0.5f * fresnel_conductor(0.6f, 0.2010055f, 3.913262f), 1e-5f);
    // Explicit eta/k, and black from below (one-sided).
    auto ek = make_bsdf("conductor", {{"eta", Color3(1.5f)}, {"k", Color3(0.f)}});
    EXPECT_NEAR(ek->sample(ctx, si, 0.3f, {0.1f, 0.2f}).second.g, fresnel_reference(0.6, 1.5), 1e-5);
    EXPECT_TRUE(ek->sample(ctx, local_si(dir(-0.6f)), 0.3f, {0.1f, 0.2f}).second.is_black());
}

TEST(PlasticBsdf, SpecularLobeWeight) {
    auto bsdf = make_bsdf("plastic", {{"diffuse_reflectance", Color3(0.5f)}});
    SurfaceInteraction si = local_si(dir(0.5f));
    BSDFContext ctx;
    const float eta = 1.49f / 1.000277f, F = fresnel_dielectric(0.5f, eta).F;
    // Mitsuba's sampling weight: specular mean / (diffuse mean + specular mean) = 1 / 1.5.
    const float ps = F * (1 / 1.5f), pd = (1 - F) * (0.5f / 1.5f), prob = ps / (ps + pd);
    auto [bs, w] = bsdf->sample(ctx, si, 0.5f * prob, {0.3f, 0.3f});
    EXPECT_EQ(bs.sampled_flags, uint32_t(bsdf_flags::DeltaReflection));
    EXPECT_NEAR(bs.pdf, prob, 1e-5f);
    EXPECT_NEAR(w.r, F / prob, 1e-4f);
    // The pdf of the diffuse lobe carries the complementary probability.
    Vec3f wo = dir(0.7f, 2.f);
    EXPECT_NEAR(bsdf->pdf(ctx, si, wo), (1 - prob) * 0.7f * InvPi, 1e-5f);
}
