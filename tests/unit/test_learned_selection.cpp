// Learned selection (integrators/guided/estimates/learned_selection.h): the second-moment sums, the fit
// and the table's bytes.
//  - a one-dimensional decision with known densities: unguided p_u = 1 on [0, 1), guided p_g = 2 on
//    [0, 1/2); samples drawn (stratified) from the pilot's mixture q = (p_u + p_g) / 2. Where the
//    integrand lives on [0, 1/2) (the guide is right) M(a) = 2 / (1 + a) and the fit picks the
//    largest share; where it lives on [1/2, 1) (the guide is wrong) M(a) = 2 / (1 - a) and the fit
//    picks 0. The sums match those integrals;
//  - too few samples keep the configured mixture; an enormous cost switches guiding off;
//  - the sums are exact: any order and any split over threads gives the same bits;
//  - the bytes round-trip, and malformed bytes (and the retired versions) are rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/estimates/learned_selection.h"
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
void add_toy(CellStatistics& stats, size_t cell, float lo, int n, int first = 0, int step = 1) {
    for (int i = first; i < n; i += step) {
        const float x = pilot_sample(i, n);
        const float p_u = 1.f, p_g = x < 0.5f ? 2.f : 0.f, q = 0.5f * (p_u + p_g);
        const float f = (x >= lo && x < lo + 0.5f) ? 2.f : 0.f;
        const double S = double(f) / double(q);
        stats.add_decision(DecisionKind::Direction, cell, S * S, q, p_u, p_g);
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
    CellStatistics stats(3);
    const int n = 20000;
    add_toy(stats, 0, 0.f, n);
    add_toy(stats, 1, 0.5f, n);
    const auto& right = stats.decision(DecisionKind::Direction, 0);
    const auto& wrong = stats.decision(DecisionKind::Direction, 1);
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
    CellStatistics stats(4);
    add_toy(stats, 0, 0.f, 2000);
    add_toy(stats, 1, 0.5f, 2000);
    add_toy(stats, 2, 0.f, 10);  // too few samples
    for (int i = 0; i < 4000; ++i) stats.add_camera_sample(1.0, 1, 0, 1);
    const LearnedSelection sel = LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f});
    ASSERT_EQ(sel.cells(), 4u);
    EXPECT_FLOAT_EQ(sel.share(DecisionKind::Direction, 0), kSelectionShares.back());
    EXPECT_FLOAT_EQ(sel.share(DecisionKind::Direction, 1), 0.f);
    EXPECT_EQ(sel.share(DecisionKind::Direction, 2), LearnedSelection::kDefault);
    EXPECT_EQ(sel.share(DecisionKind::Direction, 3), LearnedSelection::kDefault);
    EXPECT_EQ(sel.share(DecisionKind::Distance, 0), LearnedSelection::kDefault);  // no distance samples
    EXPECT_FALSE(sel.learned(DecisionKind::Distance));
    EXPECT_TRUE(sel.learned(DecisionKind::Direction));
    EXPECT_TRUE(LearnedSelection::deserialize(sel.serialize()).learned(DecisionKind::Direction));
    EXPECT_EQ(sel.share(DecisionKind::Direction, 99), LearnedSelection::kDefault);  // beyond the table
    const LearnedSelection::Summary sum = sel.summary();
    EXPECT_EQ(sum.guided[1], 1u);
    EXPECT_EQ(sum.unguided[1], 1u);

    // Shrinkage towards the pooled ratio does not overturn 2000 samples of evidence.
    SelectionSettings shrunk = plain_settings();
    shrunk.prior_samples = 64.f;
    const LearnedSelection s2 = LearnedSelection::fit(stats, shrunk, {0.5f, 0.5f, 0.5f});
    EXPECT_GT(s2.share(DecisionKind::Direction, 0), 0.5f);
    EXPECT_FLOAT_EQ(s2.share(DecisionKind::Direction, 1), 0.f);

    // A guided decision that costs far more than it saves is switched off everywhere learned.
    SelectionSettings costly = plain_settings();
    costly.kappa = {1e6f, 1e6f, 1e6f};
    const LearnedSelection s3 = LearnedSelection::fit(stats, costly, {0.5f, 0.5f, 0.5f});
    EXPECT_FLOAT_EQ(s3.share(DecisionKind::Direction, 0), 0.f);
    EXPECT_FLOAT_EQ(s3.share(DecisionKind::Direction, 1), 0.f);
    EXPECT_EQ(s3.share(DecisionKind::Direction, 2), LearnedSelection::kDefault);
}

TEST(Selection, SumsAreExactInAnyOrder) {
    ExactSum a, b;
    const double terms[] = {1e-9, 3.5, 1e12, 0.125, 7e-3, 1e15, 2e16 /* clamped */, 0.0, -1.0, NAN};
    for (double t : terms) a.add(t);
    for (int i = int(std::size(terms)) - 1; i >= 0; --i) b.add(terms[i]);
    EXPECT_EQ(a.value(), b.value());
    EXPECT_NEAR(a.value(), 2e15 + 1e12 + 3.5 + 0.125 + 7e-3, 1.0);

    // Two "threads" with interleaved halves give the statistics of one.
    CellStatistics one(2), even(2), odd(2);
    add_toy(one, 0, 0.f, 1000);
    add_toy(even, 0, 0.f, 1000, 0, 2);
    add_toy(odd, 0, 0.f, 1000, 1, 2);
    CellStatistics merged(2);
    merged += odd;
    merged += even;
    for (size_t k = 0; k < kShareCount; ++k)
        EXPECT_EQ(merged.decision(DecisionKind::Direction, 0).m[k].value(),
                  one.decision(DecisionKind::Direction, 0).m[k].value());
    EXPECT_EQ(merged.decision(DecisionKind::Direction, 0).count, 1000u);
    EXPECT_THROW(merged += CellStatistics(3), std::logic_error);  // a bug, not a user error
}

TEST(Selection, BytesRoundTripAndMalformedOnesAreRejected) {
    CellStatistics stats(3);
    add_toy(stats, 0, 0.f, 500);
    add_toy(stats, 1, 0.5f, 500);
    const LearnedSelection sel = LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f});
    const std::string bytes = sel.serialize();
    const LearnedSelection back = LearnedSelection::deserialize(bytes);
    ASSERT_EQ(back.cells(), sel.cells());
    EXPECT_TRUE(sel.learned(DecisionKind::Direction));
    for (size_t r = 0; r < sel.cells(); ++r)
        for (int d = 0; d < kDecisionKinds; ++d)
            EXPECT_EQ(back.share(DecisionKind(d), r), sel.share(DecisionKind(d), r));
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
    // A table of version 2 (with the retired continuation gate and distance method bytes): train again.
    std::string old = bytes;
    const uint32_t two_version = 2;
    std::memcpy(old.data() + 4, &two_version, sizeof two_version);
    try {
        LearnedSelection::deserialize(old);
        ADD_FAILURE() << "version 2 accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("train again"), std::string::npos) << e.what();
    }
}

// The pre-pass state carries the selection (train once, render --field everywhere with the same
// selection); pre-passes without one still read.
TEST(Selection, PrepassStateCarriesTheSelection) {
    CellStatistics stats(3);
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

// The pilot's counted costs: C_0 (decisions per camera sample) over c (mean decisions after a
// continuation point), carried by the table's bytes.
TEST(Selection, ContinuationCostRatio) {
    CellStatistics stats(2);
    add_toy(stats, 0, 0.f, 100);
    EXPECT_EQ(LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f}).continuation_cost_ratio(), 0.f);
    for (int i = 0; i < 10; ++i) stats.add_camera_sample(1.0, 20, 0, 1);
    for (int i = 0; i < 40; ++i) stats.add_continuation(ContinuationStage::Direction, 1, 0, 1.0, 5);
    const LearnedSelection sel = LearnedSelection::fit(stats, plain_settings(), {0.5f, 0.5f, 0.5f});
    EXPECT_FLOAT_EQ(sel.continuation_cost_ratio(), 4.f);
    EXPECT_FLOAT_EQ(LearnedSelection::deserialize(sel.serialize()).continuation_cost_ratio(), 4.f);
}
