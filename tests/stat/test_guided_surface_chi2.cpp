// Chi-square of the guided surface sampler (integrators/guided/walk/guided_surface_sampler.h) against its own
// mixture pdf, with the weight check (weight = exact diffuse f cos / mixture pdf): a one-lobe and a
// four-lobe incident guide and their cosine products (guiding/surface_guide.h), bsdf_prob 0 (pure
// guide, including directions below the surface, which must come back with weight 0) and 0.5, in a
// tilted shading frame (the guide lives in world space, the BSDF in the local frame). Also: without
// a guide, for a non-diffuse BSDF or with bsdf_prob 1 the sampler is the BSDF's own, bit for bit.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <ostream>

#include "support/bsdf_helpers.h"
#include "support/chi2.h"
#include "support/guiding_leaf_fixtures.h"
#include "volguide/guiding/surface_guide.h"
#include "volguide/integrators/guided/walk/guided_surface_sampler.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct SurfaceCase {
    bool multi_lobe;
    bool cosine;
    float bsdf_prob;
};

std::string name(const SurfaceCase& c) {
    return fmt::format("{}lobe_{}_bsdf{}", c.multi_lobe ? 4 : 1, c.cosine ? "cosine" : "incident",
                       int(c.bsdf_prob * 10));
}

void PrintTo(const SurfaceCase& c, std::ostream* os) {
    *os << name(c);
}

std::vector<SurfaceCase> surface_cases() {
    std::vector<SurfaceCase> out;
    for (bool multi : {false, true})
        for (bool cosine : {false, true})
            for (float p : {0.f, 0.5f}) out.push_back({multi, cosine, p});
    return out;
}

// A surface point whose shading normal is tilted away from +z, seen from the front.
SurfaceInteraction tilted_si() {
    SurfaceInteraction si;
    si.t = 1.f;
    si.sh_frame = Frame(normalize(Vec3f(0.3f, -0.2f, 0.93f)));
    si.n = Normal3f(si.sh_frame.n);
    si.wi = normalize(Vec3f(0.2f, 0.4f, 0.8f));  // local
    si.uv = Vec2f(0.3f, 0.6f);
    return si;
}

ChiSquareResult run(const GuidedSurfaceSampler& s, const BSDF& bsdf, const SurfaceInteraction& si, uint64_t seed) {
    const BSDFContext ctx;
    ChiSquareOptions opt;
    opt.test_count = int(surface_cases().size());
    opt.seed = seed;
    opt.weight_check_count = 100000;
    return chi2_test_sphere(
        [&](Sampler& smp) {
            const float u1 = smp.next_1d();
            const Point2f u2 = smp.next_2d();
            const auto r = s.sample(ctx, smp.next_1d(), u1, u2);
            return ChiSquareSample{r.bs.wo, r.weight, r.bs.pdf > 0.f};
        },
        [&](const Vec3f& wo) { return double(s.pdf(ctx, wo)); }, opt,
        [&](const Vec3f& wo) { return bsdf.eval(ctx, si, wo); });
}

class GuidedSurfaceChi2 : public ::testing::TestWithParam<SurfaceCase> {};

}  // namespace

TEST_P(GuidedSurfaceChi2, MixtureMatchesItsPdf) {
    const SurfaceCase c = GetParam();
    const auto bsdf = make_bsdf("diffuse", {{"reflectance", 0.7f}});
    const SurfaceInteraction si = tilted_si();
    const GuidingLeaf leaf = c.multi_lobe ? multi_lobe_leaf() : one_lobe_leaf();
    Vmm guide = leaf.vmm;
    if (c.cosine) {
        ASSERT_TRUE(cosine_product(leaf.vmm, si.sh_frame.n, guide));
    }
    const GuidedSurfaceSampler s(*bsdf, si, &guide, c.bsdf_prob);
    ASSERT_TRUE(s.guided());
    const auto r = run(s, *bsdf, si, 40 + uint64_t(c.multi_lobe) * 2 + uint64_t(c.cosine));
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
    EXPECT_EQ(r.weight_mismatches, 0u);
}

INSTANTIATE_TEST_SUITE_P(Guides, GuidedSurfaceChi2, ::testing::ValuesIn(surface_cases()),
                         [](const auto& info) { return name(info.param); });

TEST(GuidedSurfaceSampler, GuideDirectionsBelowTheSurfaceWeighZero) {
    const auto bsdf = make_bsdf("diffuse");
    const SurfaceInteraction si = tilted_si();
    Vmm guide;
    guide.add_lobe(1.f, VmfLobe(-si.sh_frame.n, 50.f));  // all below
    const GuidedSurfaceSampler s(*bsdf, si, &guide, 0.f);
    Sampler smp(1, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        const auto r = s.sample(BSDFContext{}, 0.9f, smp.next_1d(), smp.next_2d());
        if (r.bs.wo.z <= 0.f) {
            EXPECT_TRUE(r.weight.is_black());
        }
    }
}

TEST(GuidedSurfaceSampler, UnguidedIsExactlyTheBsdf) {
    const auto diffuse = make_bsdf("diffuse");
    const auto conductor = make_bsdf("roughconductor", {{"alpha", 0.3f}});
    const SurfaceInteraction si = tilted_si();
    const Vmm guide = multi_lobe_leaf().vmm;
    const BSDFContext ctx;
    struct Config {
        const BSDF* bsdf;
        const Vmm* guide;
        float prob;
    };
    for (const Config& c : {Config{diffuse.get(), nullptr, 0.5f}, Config{diffuse.get(), &guide, 1.f},
                            Config{conductor.get(), &guide, 0.5f}}) {
        const GuidedSurfaceSampler s(*c.bsdf, si, c.guide, c.prob);
        EXPECT_FALSE(s.guided());
        Sampler smp(3, 0, 0);
        for (int i = 0; i < 200; ++i) {
            const float u1 = smp.next_1d();
            const Point2f u2 = smp.next_2d();
            const auto [bs, w] = c.bsdf->sample(ctx, si, u1, u2);
            const auto r = s.sample(ctx, 0.f, u1, u2);
            EXPECT_EQ(r.bs.wo, bs.wo);
            EXPECT_EQ(r.bs.pdf, bs.pdf);
            EXPECT_EQ(r.weight, w);
            EXPECT_EQ(s.pdf(ctx, bs.wo), c.bsdf->pdf(ctx, si, bs.wo));
        }
    }
}
