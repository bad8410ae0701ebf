// Learned selection (guiding/selection.h): the second-moment sums, the fit and the table's bytes.
//  - a one-dimensional decision with known densities: unguided p_u = 1 on [0, 1), guided p_g = 2 on
//    [0, 1/2); samples drawn (stratified) from the pilot's mixture q = (p_u + p_g) / 2. Where the
//    integrand lives on [0, 1/2) (the guide is right) M(a) = 2 / (1 + a) and the fit picks the
//    largest share; where it lives on [1/2, 1) (the guide is wrong) M(a) = 2 / (1 - a) and the fit
//    picks 0. The sums match those integrals;
//  - too few samples keep the configured mixture; an enormous cost switches guiding off;
//  - the sums are exact: any order and any split over threads gives the same bits;
//  - guided RR/splitting acts only where the measured radiance agrees with the estimate;
//  - the bytes round-trip, and malformed bytes are rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "volguide/guiding/field_io.h"
#include "volguide/guiding/selection.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"

using namespace volguide;

namespace {

constexpr size_t kShareCount = kSelectionShares.size();

// Sample i of n from q = 1.5 on [0, 1/2), 0.5 on [1/2, 1) (stratified inversion).
float pilot_sample(int i, int n) {
    const float u = (float(i) + 0.5f) / float(n);
    return u < 0.75f ? u / 1.5f : 0.5f + (u - 0.75f) / 0.5f;
}

// Adds n decisions of `cell` whose integrand is 2 on [lo, lo + 1/2) (S = f / q, I = 1).
void add_toy(SelectionStatistics& stats, size_t cell, float lo, int n, int first = 0, int step = 1) {
    for (int i = first; i < n; i += step) {
        const float x = pilot_sample(i, n);
        const float p_u = 1.f, p_g = x < 0.5f ? 2.f : 0.f, q = 0.5f * (p_u + p_g);
        const float f = (x >= lo && x < lo + 0.5f) ? 2.f : 0.f;
        const double S = double(f) / double(q);
        stats.add_decision(SelectionDecision::Direction, cell, S * S, q, p_u, p_g);
    }
}

SelectionSettings plain_settings() {
    SelectionSettings s;
    s.min_samples = 32;
    s.prior_samples = 0.f;  // no shrinkage: the cells' own estimates
    return s;
}

}  // namespace

TEST(Selection, SecondMomentsMatchTheIntegrals) {
    SelectionStatistics stats(3);
    const int n = 20000;
    add_toy(stats, 0, 0.f, n);
    add_toy(stats, 1, 0.5f, n);
    const auto& right = stats.moments(SelectionDecision::Direction, 0);
    const auto& wrong = stats.moments(SelectionDecision::Direction, 1);
    EXPECT_EQ(right.count, uint64_t(n));
    for (size_t k = 0; k < kShareCount; ++k) {
        const double a = kSelectionShares[k];
        EXPECT_NEAR(right.m[k].value() / n, 2.0 / (1.0 + a), 2e-3) << "share " << a;
        EXPECT_NEAR(wrong.m[k].value() / n, 2.0 / (1.0 - a), 2e-3 * 2.0 / (1.0 - a)) << "share " << a;
    }
    // The pilot's own share (0.5): M = sum of S^2.
    EXPECT_NEAR(right.current.value() / n, 2.0 / 1.5, 2e-3);
}

TEST(Selection, FitFollowsTheGuideWhereItIsRightAndDropsItWhereItIsWrong) {
    SelectionStatistics stats(4);
    add_toy(stats, 0, 0.f, 2000);
    add_toy(stats, 1, 0.5f, 2000);
    add_toy(stats, 2, 0.f, 10);  // too few samples
    for (int i = 0; i < 4000; ++i) stats.add_camera_sample(1.0);
    const LearnedSelection sel = LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f});
    ASSERT_EQ(sel.cells(), 4u);
    EXPECT_FLOAT_EQ(sel.share(SelectionDecision::Direction, 0), kSelectionShares.back());
    EXPECT_FLOAT_EQ(sel.share(SelectionDecision::Direction, 1), 0.f);
    EXPECT_EQ(sel.share(SelectionDecision::Direction, 2), LearnedSelection::kDefault);
    EXPECT_EQ(sel.share(SelectionDecision::Direction, 3), LearnedSelection::kDefault);
    EXPECT_EQ(sel.share(SelectionDecision::Distance, 0), LearnedSelection::kDefault);  // no distance samples
    EXPECT_FALSE(sel.learned(SelectionDecision::Distance));
    EXPECT_TRUE(sel.learned(SelectionDecision::Direction));
    EXPECT_TRUE(LearnedSelection::deserialize(sel.serialize()).learned(SelectionDecision::Direction));
    EXPECT_EQ(sel.share(SelectionDecision::Direction, 99), LearnedSelection::kDefault);  // beyond the table
    const LearnedSelection::Summary sum = sel.summary();
    EXPECT_EQ(sum.guided[1], 1u);
    EXPECT_EQ(sum.unguided[1], 1u);

    // Shrinkage towards the pooled ratio does not overturn 2000 samples of evidence.
    SelectionSettings shrunk = plain_settings();
    shrunk.prior_samples = 64.f;
    const LearnedSelection s2 = LearnedSelection::fit(stats, shrunk, {0.5f, 0.5f, 0.5f});
    EXPECT_GT(s2.share(SelectionDecision::Direction, 0), 0.5f);
    EXPECT_FLOAT_EQ(s2.share(SelectionDecision::Direction, 1), 0.f);

    // A guided decision that costs far more than it saves is switched off everywhere learned.
    SelectionSettings costly = plain_settings();
    costly.kappa = {1e6f, 1e6f, 1e6f};
    const LearnedSelection s3 = LearnedSelection::fit(stats, costly, {0.5f, 0.5f, 0.5f});
    EXPECT_FLOAT_EQ(s3.share(SelectionDecision::Direction, 0), 0.f);
    EXPECT_FLOAT_EQ(s3.share(SelectionDecision::Direction, 1), 0.f);
    EXPECT_EQ(s3.share(SelectionDecision::Direction, 2), LearnedSelection::kDefault);
}

TEST(Selection, SumsAreExactInAnyOrder) {
    ExactSum a, b;
    const double terms[] = {1e-9, 3.5, 1e12, 0.125, 7e-3, 1e15, 2e16 /* clamped */, 0.0, -1.0, NAN};
    for (double t : terms) a.add(t);
    for (int i = int(std::size(terms)) - 1; i >= 0; --i) b.add(terms[i]);
    EXPECT_EQ(a.value(), b.value());
    EXPECT_NEAR(a.value(), 2e15 + 1e12 + 3.5 + 0.125 + 7e-3, 1.0);

    // Two "threads" with interleaved halves give the statistics of one.
    SelectionStatistics one(2), even(2), odd(2);
    add_toy(one, 0, 0.f, 1000);
    add_toy(even, 0, 0.f, 1000, 0, 2);
    add_toy(odd, 0, 0.f, 1000, 1, 2);
    SelectionStatistics merged(2);
    merged += odd;
    merged += even;
    for (size_t k = 0; k < kShareCount; ++k)
        EXPECT_EQ(merged.moments(SelectionDecision::Direction, 0).m[k].value(),
                  one.moments(SelectionDecision::Direction, 0).m[k].value());
    EXPECT_EQ(merged.moments(SelectionDecision::Direction, 0).count, 1000u);
    EXPECT_THROW(merged += SelectionStatistics(3), std::logic_error);
}

TEST(Selection, RouletteActsWhereTheEstimateAgreesWithThePaths) {
    SelectionStatistics stats(4);
    for (int i = 0; i < 100; ++i) {
        stats.add_continuation(0, 0, 1.0, 1.5);  // agrees within 3x
        stats.add_continuation(0, 1, 1.0, 10.0);  // the leaf is estimated 10x too dark
        stats.add_continuation(1, 1, 1.0, 0.9);
        stats.add_continuation(0, 2, 1.0, 0.1);  // 10x too bright
    }
    for (int i = 0; i < 5; ++i) stats.add_continuation(0, 3, 1.0, 100.0);  // too few to judge
    SelectionSettings gated = plain_settings();
    EXPECT_EQ(gated.rrs_ratio, 0.f);  // off by default: acts everywhere
    EXPECT_FALSE(LearnedSelection::fit(stats, gated, {0.5f, 0.5f, 0.5f}).summary().rrs_off);
    gated.rrs_ratio = 3.f;
    const LearnedSelection sel = LearnedSelection::fit(stats, gated, {0.5f, 0.5f, 0.5f});
    EXPECT_TRUE(sel.rrs_acts(0, 0));
    EXPECT_FALSE(sel.rrs_acts(0, 1));
    EXPECT_TRUE(sel.rrs_acts(1, 1));
    EXPECT_FALSE(sel.rrs_acts(0, 2));
    EXPECT_TRUE(sel.rrs_acts(0, 3));
    EXPECT_TRUE(sel.rrs_acts(0, 1000));  // beyond the table: acts
    EXPECT_EQ(sel.summary().rrs_off, 2u);
}

TEST(Selection, BytesRoundTripAndMalformedOnesAreRejected) {
    SelectionStatistics stats(3);
    add_toy(stats, 0, 0.f, 500);
    add_toy(stats, 1, 0.5f, 500);
    for (int i = 0; i < 100; ++i) stats.add_continuation(1, 1, 1.0, 10.0);
    SelectionSettings gated = plain_settings();
    gated.rrs_ratio = 3.f;
    const LearnedSelection sel = LearnedSelection::fit(stats, gated, {0.5f, 0.5f, 0.5f});
    const std::string bytes = sel.serialize();
    const LearnedSelection back = LearnedSelection::deserialize(bytes);
    ASSERT_EQ(back.cells(), sel.cells());
    for (size_t r = 0; r < sel.cells(); ++r) {
        for (int d = 0; d < kSelectionDecisions; ++d)
            EXPECT_EQ(back.share(SelectionDecision(d), r), sel.share(SelectionDecision(d), r));
        for (int s = 0; s < kSelectionStages; ++s) EXPECT_EQ(back.rrs_acts(s, r), sel.rrs_acts(s, r));
    }
    EXPECT_THROW(LearnedSelection::deserialize(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
    EXPECT_THROW(LearnedSelection::deserialize(bytes + "x"), std::runtime_error);
    EXPECT_THROW(LearnedSelection::deserialize(""), std::runtime_error);
    std::string bad_magic = bytes;
    bad_magic[0] ^= 1;
    EXPECT_THROW(LearnedSelection::deserialize(bad_magic), std::runtime_error);
    std::string bad_share = bytes;
    const float two = 2.f;
    std::memcpy(bad_share.data() + 16, &two, sizeof two);  // the first cell's distance share
    EXPECT_THROW(LearnedSelection::deserialize(bad_share), std::runtime_error);
    std::string huge = bytes;
    const uint64_t n = uint64_t(1) << 60;
    std::memcpy(huge.data() + 8, &n, sizeof n);
    EXPECT_THROW(LearnedSelection::deserialize(huge), std::runtime_error);
}

// The pre-pass state carries the selection (train once, render --field everywhere with the same
// selection); pre-passes without one still read.
TEST(Selection, PrepassStateCarriesTheSelection) {
    SelectionStatistics stats(3);
    add_toy(stats, 0, 0.f, 500);
    add_toy(stats, 1, 0.5f, 500);
    const std::string sel = LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f}).serialize();
    Image estimate(2, 1);
    estimate.at(0, 0) = Color3(1.f, 2.f, 3.f);
    std::vector<RadianceSample> samples;
    for (int i = 0; i < 64; ++i)
        samples.push_back({Point3f(float(i % 4) / 4.f + 0.1f, float(i / 16) / 4.f + 0.1f, 0.5f), Vec3f(0.f, 0.f, 1.f),
                           Color3(1.f)});
    const GuidingField field = GuidingField::build(BBox3f(Point3f(0.f), Point3f(1.f)), samples, GuidingFieldSettings());
    const GuidedPrepass with = deserialize_guided_prepass(serialize_guided_prepass(field, estimate, sel));
    EXPECT_EQ(with.selection, sel);
    EXPECT_EQ(with.pixel_estimate.at(0, 0).g, 2.f);
    const GuidedPrepass without = deserialize_guided_prepass(serialize_guided_prepass(field, estimate));
    EXPECT_TRUE(without.selection.empty());
    const GuidedPrepass no_estimate = deserialize_guided_prepass(serialize_guided_prepass(field, Image(), sel));
    EXPECT_EQ(no_estimate.selection, sel);
    const std::string bytes = serialize_guided_prepass(field, estimate, sel);
    EXPECT_THROW(deserialize_guided_prepass(bytes.substr(0, bytes.size() - 3)), FieldFormatError);
    std::string corrupt = bytes;
    corrupt[bytes.size() - sel.size()] ^= 1;  // the selection's magic
    EXPECT_THROW(deserialize_guided_prepass(corrupt), FieldFormatError);
}

// Per-cell method (issue 37, docs/theory.md §7.12) on synthetic round statistics: every round has
// the same camera samples; cells 0 and 1 get `per_decision` second moments per method, `lookups` per
// distance decision, and every guided round a guided direction decision per distance decision (the
// volpath round none).
namespace {
void add_method_rounds(SelectionStatistics& stats, const std::array<double, kDistanceMethods>& per_decision,
                       const std::array<uint64_t, kDistanceMethods>& lookups, int n) {
    for (int k = 0; k < kDistanceMethods; ++k) {
        const DistanceMethod m = DistanceMethod(k);
        for (size_t cell = 0; cell < 2; ++cell)
            for (int i = 0; i < n; ++i) {
                stats.add_method_decision(m, cell, per_decision[size_t(k)], lookups[size_t(k)]);
                if (m != DistanceMethod::Volpath) stats.add_method_event(m, cell, CostEvent::GuidedDirection);
            }
        for (int i = 0; i < n; ++i) stats.add_method_camera_sample(m, 4.0, {2, 2, 1});
    }
}

SelectionSettings method_settings() {
    SelectionSettings s = plain_settings();
    s.choose_distance_method = true;
    return s;
}

// Every event of the cost model costs the same (1 ns; no bin lookups, no guided extras): only the
// variances decide.
SelectionSettings flat_cost_settings() {
    SelectionSettings s = method_settings();
    s.costs.segment = 1.f;
    s.costs.decision = {0.f, 0.f, 0.f, 0.f, 0.f};
    s.costs.bin_lookup = s.costs.guided_direction = s.costs.guided_surface = s.costs.estimate = 0.f;
    return s;
}
}  // namespace

TEST(Selection, EqualVariancesChooseTheCheapestMethod) {
    SelectionStatistics stats(3);
    // Every guided round pays the guided direction decision: volpath is the cheapest.
    add_method_rounds(stats, {1.0, 1.0, 1.0, 1.0, 1.0}, {0, 1, 6, 8, 0}, 200);
    const LearnedSelection sel = LearnedSelection::fit(stats, method_settings(), {0.5f, 0.5f, 0.5f});
    for (size_t r = 0; r < 2; ++r) {
        EXPECT_EQ(sel.distance_method(r), uint8_t(DistanceMethod::Volpath));
        EXPECT_TRUE(sel.volpath(r));
        for (int d = 0; d < kSelectionDecisions; ++d) EXPECT_EQ(sel.share(SelectionDecision(d), r), 0.f);
        EXPECT_FALSE(sel.rrs_acts(0, r));
        EXPECT_FALSE(sel.rrs_acts(1, r));
    }
    // The cell without decisions follows the cells with too few (none here: volpath).
    EXPECT_EQ(sel.distance_method(2), uint8_t(DistanceMethod::Volpath));
    EXPECT_TRUE(sel.has_volpath_cells());
    EXPECT_EQ(sel.summary().methods[size_t(DistanceMethod::Volpath)], 3u);
    // Without the guided direction's cost free flight costs what volpath does: a full tie goes to
    // volpath; free flight's variance a little lower, free flight (the directions stay guided).
    SelectionSettings no_direction = method_settings();
    no_direction.costs.guided_direction = 0.f;
    EXPECT_EQ(LearnedSelection::fit(stats, no_direction, {0.5f, 0.5f, 0.5f}).distance_method(0),
              uint8_t(DistanceMethod::Volpath));
    SelectionStatistics lower(3);
    add_method_rounds(lower, {0.99, 1.0, 1.0, 1.0, 1.0}, {0, 1, 6, 8, 0}, 200);
    const LearnedSelection ff = LearnedSelection::fit(lower, no_direction, {0.5f, 0.5f, 0.5f});
    EXPECT_EQ(ff.distance_method(0), uint8_t(DistanceMethod::FreeFlight));
    EXPECT_EQ(ff.share(SelectionDecision::Distance, 0), 0.f);
    EXPECT_EQ(ff.share(SelectionDecision::Direction, 0), LearnedSelection::kDefault);  // still guided
    EXPECT_FALSE(ff.volpath(0));
}

TEST(Selection, EqualCostsChooseTheLowestVarianceMethod) {
    for (int best = 0; best < kDistanceMethods; ++best) {
        SelectionStatistics stats(3);
        std::array<double, kDistanceMethods> m = {2.0, 2.0, 2.0, 2.0, 2.0};
        m[size_t(best)] = 0.5;
        add_method_rounds(stats, m, {3, 3, 3, 3, 3}, 200);
        const LearnedSelection sel = LearnedSelection::fit(stats, flat_cost_settings(), {0.5f, 0.5f, 0.5f});
        EXPECT_EQ(sel.distance_method(0), uint8_t(best));
        EXPECT_EQ(sel.distance_method(1), uint8_t(best));
        // A guided method keeps the configured distance mixture; free flight and volpath are share 0.
        const bool unguided = best == int(DistanceMethod::FreeFlight) || best == int(DistanceMethod::Volpath);
        EXPECT_EQ(sel.share(SelectionDecision::Distance, 0), unguided ? 0.f : LearnedSelection::kDefault);
        EXPECT_EQ(sel.volpath(0), best == int(DistanceMethod::Volpath));
        EXPECT_TRUE(sel.learned(SelectionDecision::Distance));
    }
}

TEST(Selection, VarianceIsWeighedAgainstCost) {
    // The product halves the variance: worth it when its decision is cheap, not when it costs as
    // much as a thousand segments.
    SelectionStatistics stats(3);
    add_method_rounds(stats, {2.0, 2.0, 1.0, 2.0, 2.0}, {0, 1, 8, 8, 0}, 200);
    SelectionSettings cheap = flat_cost_settings();
    cheap.costs.decision[size_t(DistanceMethod::VspProduct)] = 0.1f;
    EXPECT_EQ(LearnedSelection::fit(stats, cheap, {0.5f, 0.5f, 0.5f}).distance_method(0),
              uint8_t(DistanceMethod::VspProduct));
    SelectionSettings dear = flat_cost_settings();
    dear.costs.decision[size_t(DistanceMethod::VspProduct)] = 1000.f;
    EXPECT_NE(LearnedSelection::fit(stats, dear, {0.5f, 0.5f, 0.5f}).distance_method(0),
              uint8_t(DistanceMethod::VspProduct));
    // Without the method choice nothing of it is learned.
    EXPECT_EQ(LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f}).distance_method(0), kMethodDefault);
}

// The brief's two cells: in cell 0 guiding (vsp) lowers the second moment by 5 % at a guided
// vertex's cost (a guided direction, ~2.5x a volpath segment): it costs more than it saves, volpath.
// In cell 1 it lowers it 10x: guided.
TEST(Selection, VolpathWhereGuidingCostsMoreThanItSaves) {
    SelectionStatistics stats(3);
    const int n = 400;
    for (int k = 0; k < kDistanceMethods; ++k) {
        const DistanceMethod m = DistanceMethod(k);
        const bool guided = m != DistanceMethod::Volpath && m != DistanceMethod::FreeFlight;
        for (int i = 0; i < n; ++i) {
            stats.add_method_decision(m, 0, guided ? 0.95 : 1.0, m == DistanceMethod::Bins ? 8 : 1);
            stats.add_method_decision(m, 1, guided ? 0.1 : 1.0, m == DistanceMethod::Bins ? 8 : 1);
            if (m != DistanceMethod::Volpath) {
                stats.add_method_event(m, 0, CostEvent::GuidedDirection);
                stats.add_method_event(m, 1, CostEvent::GuidedDirection);
            }
            stats.add_method_camera_sample(m, 1.0, {2, 1, 0});
        }
    }
    const LearnedSelection sel = LearnedSelection::fit(stats, method_settings(), {0.5f, 0.5f, 0.5f});
    EXPECT_EQ(sel.distance_method(0), uint8_t(DistanceMethod::Volpath));
    EXPECT_EQ(sel.distance_method(1), uint8_t(DistanceMethod::Vsp));  // the cheapest of the guided three
    const LearnedSelection::Summary sum = sel.summary();
    EXPECT_GE(sum.methods[size_t(DistanceMethod::Volpath)], 1u);
    EXPECT_EQ(sum.methods[size_t(DistanceMethod::Vsp)], 1u);
}

// method_cell_cost: each counted event times its constant; the bins' lookups only in the bins'
// round, the estimate reads not in volpath's, guided splitting's extra and roulette's savings added.
TEST(Selection, CellCostCountsEveryEvent) {
    SelectionStatistics stats(2);
    SelectionCosts c;
    c.segment = 100.f;
    c.decision = {1.f, 2.f, 3.f, 4.f, 5.f};
    c.bin_lookup = 10.f;
    c.guided_direction = 1000.f;
    c.guided_surface = 2000.f;
    c.estimate = 7.f;
    for (int k = 0; k < kDistanceMethods; ++k) {
        const DistanceMethod m = DistanceMethod(k);
        stats.add_method_decision(m, 0, 1.0, 3);
        stats.add_method_decision(m, 0, 1.0, 1);
        stats.add_method_event(m, 0, CostEvent::GuidedDirection);
        stats.add_method_event(m, 0, CostEvent::GuidedSurface, 2);
        stats.add_method_event(m, 0, CostEvent::Continuation, 3);
    }
    stats.add_method_split_cost(DistanceMethod::Vsp, 0, 500.0);
    stats.add_method_split_cost(DistanceMethod::Vsp, 0, -200.0);
    const double common = 2 * 100.0 + 1000.0 + 2 * 2000.0;
    EXPECT_DOUBLE_EQ(method_cell_cost(stats, c, DistanceMethod::FreeFlight, 0), common + 2 * 1.0 + 3 * 7.0);
    EXPECT_DOUBLE_EQ(method_cell_cost(stats, c, DistanceMethod::Vsp, 0), common + 2 * 2.0 + 3 * 7.0 + 300.0);
    EXPECT_DOUBLE_EQ(method_cell_cost(stats, c, DistanceMethod::Bins, 0), common + 2 * 4.0 + 4 * 10.0 + 3 * 7.0);
    EXPECT_DOUBLE_EQ(method_cell_cost(stats, c, DistanceMethod::Volpath, 0), common + 2 * 5.0);
    EXPECT_DOUBLE_EQ(method_cell_cost(stats, c, DistanceMethod::Vsp, 1), 0.0);
    // Per camera sample of a round: the cells' costs and the surface decisions' segments.
    stats.add_method_camera_sample(DistanceMethod::Vsp, 1.0, {2, 1, 3});
    stats.add_method_camera_sample(DistanceMethod::Vsp, 1.0, {0, 0, 1});
    EXPECT_DOUBLE_EQ(method_round_cost_per_sample(stats, c, DistanceMethod::Vsp),
                     (common + 2 * 2.0 + 3 * 7.0 + 300.0 + 4 * 100.0) / 2.0);
}

TEST(Selection, CellsWithFewSamplesChooseTogether) {
    // Cells 0 and 1 have 200 decisions per round, cell 2 ten (below min_samples): cell 2 follows
    // its own sums (the product, lowest in variance there by far), not the configured method.
    SelectionStatistics stats(3);
    add_method_rounds(stats, {1.0, 1.0, 1.0, 1.0, 1.0}, {0, 1, 6, 8, 0}, 200);
    for (int k = 0; k < kDistanceMethods; ++k)
        for (int i = 0; i < 10; ++i)
            stats.add_method_decision(DistanceMethod(k), 2, k == int(DistanceMethod::VspProduct) ? 1.0 : 1e4, 0);
    const LearnedSelection sel = LearnedSelection::fit(stats, method_settings(), {0.5f, 0.5f, 0.5f});
    EXPECT_EQ(sel.distance_method(0), uint8_t(DistanceMethod::Volpath));
    EXPECT_EQ(sel.distance_method(2), uint8_t(DistanceMethod::VspProduct));
}

TEST(Selection, MethodsRoundTripAndForcedRounds) {
    SelectionStatistics stats(4);
    add_method_rounds(stats, {2.0, 1.0, 2.0, 2.0, 2.0}, {0, 1, 6, 8, 0}, 200);
    // Cell 2: volpath has the lowest second moment.
    for (int k = 0; k < kDistanceMethods; ++k)
        for (int i = 0; i < 200; ++i)
            stats.add_method_decision(DistanceMethod(k), 2, k == int(DistanceMethod::Volpath) ? 0.5 : 1.0, 0);
    const LearnedSelection sel = LearnedSelection::fit(stats, flat_cost_settings(), {0.5f, 0.5f, 0.5f});
    ASSERT_EQ(sel.distance_method(0), uint8_t(DistanceMethod::Vsp));
    ASSERT_TRUE(sel.volpath(2));
    const LearnedSelection back = LearnedSelection::deserialize(sel.serialize());
    for (size_t r = 0; r < 4; ++r) {
        EXPECT_EQ(back.distance_method(r), sel.distance_method(r));
        EXPECT_EQ(back.volpath(r), sel.volpath(r));
        for (int d = 0; d < kSelectionDecisions; ++d)
            EXPECT_EQ(back.share(SelectionDecision(d), r), sel.share(SelectionDecision(d), r));
        EXPECT_EQ(back.rrs_acts(0, r), sel.rrs_acts(0, r));
    }
    EXPECT_EQ(back.has_volpath_cells(), sel.has_volpath_cells());
    std::string bad = sel.serialize();
    bad[16 + kSelectionDecisions * sizeof(float) + kSelectionStages] = 7;  // the first cell's method
    EXPECT_THROW(LearnedSelection::deserialize(bad), std::runtime_error);
    const LearnedSelection forced = LearnedSelection::forced_method(4, DistanceMethod::Bins);
    EXPECT_EQ(forced.cells(), 4u);
    EXPECT_EQ(forced.distance_method(3), uint8_t(DistanceMethod::Bins));
    EXPECT_EQ(forced.share(SelectionDecision::Distance, 3), LearnedSelection::kDefault);
    EXPECT_TRUE(forced.learned(SelectionDecision::Distance));
    EXPECT_FALSE(forced.learned(SelectionDecision::Direction));
    EXPECT_FALSE(forced.has_volpath_cells());
    // The volpath round: every decision unguided, guided RR/splitting off, in every cell.
    const LearnedSelection volpath = LearnedSelection::forced_method(4, DistanceMethod::Volpath);
    EXPECT_TRUE(volpath.has_volpath_cells());
    for (size_t r = 0; r < 4; ++r) {
        EXPECT_TRUE(volpath.volpath(r));
        for (int d = 0; d < kSelectionDecisions; ++d) EXPECT_EQ(volpath.share(SelectionDecision(d), r), 0.f);
        EXPECT_FALSE(volpath.rrs_acts(1, r));
    }
    EXPECT_FALSE(volpath.volpath(4));  // beyond the table: not learned
    const LearnedSelection volpath_back = LearnedSelection::deserialize(volpath.serialize());
    EXPECT_TRUE(volpath_back.volpath(3));
}
