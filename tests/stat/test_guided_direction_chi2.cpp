// Chi-square of the guided directional sampler (docs/theory.md §8.2, §14.6) against its own full
// mixture pdf, with the weight check eval = exact HG: Product and Incident guides, alpha_f = 0
// (pure VMM part) and 0.5, one-, four- and 13-lobe leaves (the vectorised product over two blocks of lanes), HG g in {0, 0.5, 0.9, -0.6}; the phase-only
// fallback of an invalid leaf against the HG pdf; and a control that a wrong pdf is rejected.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <ostream>
#include <vector>

#include "support/chi2.h"
#include "support/guiding_leaf_fixtures.h"
#include "volguide/guiding/guided_direction.h"
#include "volguide/media/phase_hg.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct DirectionCase {
    DirectionGuiding mode;
    int lobes;  // 1, 4 (multi_lobe_leaf) or 13 (spiral_leaf: two blocks of vector lanes)
    float g;
    float alpha;
};

std::string name(const DirectionCase& c) {
    return fmt::format("{}_{}lobe_g{}_alpha{}", c.mode == DirectionGuiding::Product ? "Product" : "Incident",
                       c.lobes, c.g, c.alpha);
}

void PrintTo(const DirectionCase& c, std::ostream* os) {
    *os << name(c);
}

// Incident with alpha_f = 0 does not depend on g: one g per leaf.
std::vector<DirectionCase> direction_cases() {
    std::vector<DirectionCase> out;
    for (int lobes : {1, 4, 13})
        for (float g : {0.f, 0.5f, 0.9f, -0.6f})
            for (float alpha : {0.f, 0.5f}) {
                out.push_back({DirectionGuiding::Product, lobes, g, alpha});
                if (alpha > 0.f || g == 0.5f) out.push_back({DirectionGuiding::Incident, lobes, g, alpha});
            }
    return out;
}

const int kDirectionTestCount = int(direction_cases().size()) + 1;  // + the invalid-leaf fallback

// check_weights: every sample's weight must equal the exact HG over `pdf`.
ChiSquareResult run(const GuidedDirectionSampler& sampler, const ChiSquarePdfFn& pdf, uint64_t seed,
                    bool check_weights = true, uint64_t samples = 1000000) {
    ChiSquareOptions opt;
    opt.sample_count = samples;
    opt.weight_check_count = 100000;
    opt.test_count = kDirectionTestCount;
    opt.seed = seed;
    return chi2_test_sphere(
        [&](Sampler& s) {
            const Point2f u = s.next_2d();
            const auto r = sampler.sample(u, s.next_1d());
            return ChiSquareSample{r.wo, Color3(r.weight), r.pdf > 0.f};
        },
        pdf, opt,
        check_weights ? ChiSquareEvalFn([&](const Vec3f& d) { return Color3(sampler.eval_phase(d)); })
                      : ChiSquareEvalFn());
}

class GuidedDirectionChi2 : public ::testing::TestWithParam<DirectionCase> {};

}  // namespace

TEST_P(GuidedDirectionChi2, MixtureMatchesItsPdf) {
    const DirectionCase c = GetParam();
    const GuidingLeaf leaf = c.lobes == 1 ? one_lobe_leaf() : c.lobes == 4 ? multi_lobe_leaf() : spiral_leaf(c.lobes);
    const HGPhase phase(c.g);
    const GuidedDirectionSampler sampler(c.mode, &leaf, phase, test_wi(), c.alpha);
    ASSERT_TRUE(sampler.guided());
    const auto r = run(
        sampler, [&](const Vec3f& d) { return double(sampler.pdf(d)); }, 100 + uint64_t(int64_t(c.g * 10)));
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3);
    EXPECT_EQ(r.weight_mismatches, 0u);
}

INSTANTIATE_TEST_SUITE_P(Guides, GuidedDirectionChi2, ::testing::ValuesIn(direction_cases()), [](const auto& info) {
    std::string n = name(info.param);
    for (char& ch : n)
        if (ch == '.' || ch == '-') ch = ch == '.' ? 'p' : 'm';
    return n;
});

TEST(GuidedDirectionChi2Fallback, InvalidLeafSamplesThePhaseFunction) {
    GuidingLeaf leaf = multi_lobe_leaf();
    leaf.valid = false;
    const HGPhase phase(0.7f);
    const Vec3f wi = test_wi();
    const GuidedDirectionSampler sampler(DirectionGuiding::Product, &leaf, phase, wi, 0.5f);
    ASSERT_FALSE(sampler.guided());
    const auto r = run(
        sampler, [&](const Vec3f& d) { return double(phase.pdf(wi, d)); }, 7);
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(GuidedDirectionChi2Control, WrongMixtureWeightIsRejected) {
    // Samples drawn with alpha_f = 0.5 tested against the pdf of alpha_f = 0.35 (histogram only,
    // the weights would fail anyway): must fail.
    const GuidingLeaf leaf = multi_lobe_leaf();
    const HGPhase phase(0.5f);
    const Vec3f wi = test_wi();
    const GuidedDirectionSampler sampler(DirectionGuiding::Product, &leaf, phase, wi, 0.5f);
    const GuidedDirectionSampler claimed(DirectionGuiding::Product, &leaf, phase, wi, 0.35f);
    const auto r = run(
        sampler, [&](const Vec3f& d) { return double(claimed.pdf(d)); }, 9, false, 200000);
    EXPECT_FALSE(r.passed) << r.report;
}
