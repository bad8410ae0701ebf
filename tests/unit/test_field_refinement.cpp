// FieldRefinement (issue 39, docs/theory.md §22): a photon field that takes further passes into per-leaf
// statistics, splits leaves with the budget, merges siblings where the light is smooth, and stays
// within max_leaves.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "volguide/core/sampler.h"
#include "volguide/guiding/field_refinement.h"

namespace volguide {
namespace {

const BBox3f kRefineBox(Point3f(0.f), Point3f(1.f));

Vec3f refine_around(const Vec3f& axis, Sampler& s, float spread) {
    const Vec3f d(axis.x + spread * (s.next_1d() - 0.5f), axis.y + spread * (s.next_1d() - 0.5f),
                  axis.z + spread * (s.next_1d() - 0.5f));
    return normalize(d);
}

// A photon pass of n photons, one deposit each (weights divided by n as trace_photons leaves them):
// uniform positions; on x < 1/2 fluence 1 arriving around +z, on x >= 1/2 fluence 4 around -x
// (`structured`), or fluence 1 around +z everywhere.
std::vector<RadianceSample> refine_pass(int n, uint64_t seed, bool structured = true) {
    std::vector<RadianceSample> out(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        Sampler s(seed, 7, uint64_t(i));
        RadianceSample& r = out[size_t(i)];
        r.position = Point3f(s.next_1d(), s.next_1d(), s.next_1d());
        const bool right = structured && r.position.x >= 0.5f;
        r.direction = refine_around(right ? Vec3f(-1, 0, 0) : Vec3f(0, 0, 1), s, 0.3f);
        r.weight = Color3(right ? 4.f : 1.f) * (1.f / float(n));
    }
    return out;
}

FieldRefinementSettings refine_settings() {
    FieldRefinementSettings s;
    s.field.tree.max_samples = 500;
    s.field.lobes = 4;
    s.field.min_samples = 32;
    return s;
}

bool same_field(const GuidingField& a, const GuidingField& b) {
    if (a.tree().leaf_count() != b.tree().leaf_count() || a.tree().nodes().size() != b.tree().nodes().size()) return false;
    for (size_t k = 0; k < a.tree().nodes().size(); ++k) {
        const auto &na = a.tree().nodes()[k], &nb = b.tree().nodes()[k];
        if (na.split != nb.split || na.axis != nb.axis || na.child != nb.child) return false;
    }
    for (size_t l = 0; l < a.leaves().size(); ++l) {
        const GuidingLeaf &la = a.leaves()[l], &lb = b.leaves()[l];
        if (std::memcmp(&la.fluence, &lb.fluence, sizeof(Color3)) != 0 || la.valid != lb.valid ||
            la.vmm.count != lb.vmm.count)
            return false;
        for (int k = 0; k < la.vmm.count; ++k)
            if (la.vmm.weight[k] != lb.vmm.weight[k] || la.vmm.kappa[k] != lb.vmm.kappa[k] || la.vmm.mu_x[k] != lb.vmm.mu_x[k])
                return false;
    }
    return true;
}

// Before any further pass the refinement's field is the pre-pass's: the same tree, fluence, mixtures.
TEST(FieldRefinement, StartsAsTheBuiltField) {
    const auto pass = refine_pass(8000, 1);
    const FieldRefinementSettings rs = refine_settings();
    const GuidingField built = GuidingField::build(kRefineBox, pass, rs.field);
    const FieldRefinement refinement(built, pass, 8000.0, rs);
    const GuidingField f = refinement.field();
    ASSERT_EQ(f.tree().leaf_count(), built.tree().leaf_count());
    for (size_t l = 0; l < f.leaves().size(); ++l) {
        const GuidingLeaf &a = f.leaves()[l], &b = built.leaves()[l];
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.fluence[c], b.fluence[c], 1e-5f * b.fluence[c]) << l;
        EXPECT_EQ(a.valid, b.valid);
        ASSERT_EQ(a.vmm.count, b.vmm.count);
        for (int k = 0; k < a.vmm.count; ++k) EXPECT_EQ(a.vmm.kappa[k], b.vmm.kappa[k]);
    }
    EXPECT_GT(refinement.memory_bytes(), 0u);
}

// Further passes: the leaves split as the photons grow (threshold 500 x sqrt(photons / first); merging
// off, or the uniform halves would merge back), the fluence stays each half's (1 and 4), each leaf's
// mixture points where its light comes from.
TEST(FieldRefinement, FurtherPassesRefineTheLeavesAndKeepTheFluence) {
    FieldRefinementSettings rs = refine_settings();
    rs.merge_contrast = 0.f;
    const auto first = refine_pass(8000, 1);
    FieldRefinement refinement(GuidingField::build(kRefineBox, first, rs.field), first, 8000.0, rs);
    const int initial = refinement.leaf_count();
    int splits = 0;
    for (uint64_t p = 2; p <= 4; ++p) {
        const RefinementReport r = refinement.add(refine_pass(int(8000 << (p - 1)), p), double(8000 << (p - 1)));
        splits += r.leaf_splits;
        EXPECT_EQ(r.leaves, refinement.leaf_count());
    }
    EXPECT_GT(splits, 0);
    EXPECT_GT(refinement.leaf_count(), initial);
    const GuidingField f = refinement.field();
    for (size_t l = 0; l < f.leaves().size(); ++l) {
        const BBox3f& b = f.tree().leaf_bounds(int(l));
        const GuidingLeaf& leaf = f.leaves()[l];
        if (b.hi.x <= 0.5f) {
            EXPECT_NEAR(leaf.fluence.r, 1.f, 0.2f) << l;
        } else if (b.lo.x >= 0.5f) {
            EXPECT_NEAR(leaf.fluence.r, 4.f, 0.8f) << l;
        } else {
            continue;  // a leaf across the boundary averages the two
        }
        ASSERT_TRUE(leaf.valid) << l;
        const bool right = b.lo.x >= 0.5f;
        const Vec3f toward = right ? Vec3f(-1, 0, 0) : Vec3f(0, 0, 1), away = right ? Vec3f(0, 0, 1) : Vec3f(-1, 0, 0);
        EXPECT_GT(leaf.vmm.pdf(toward), 20.f * leaf.vmm.pdf(away)) << l;
    }
}

// Where the light is the same everywhere, siblings merge (fewer leaves than without merging); never
// more leaves than max_leaves.
TEST(FieldRefinement, MergesSmoothSiblingsAndBoundsTheLeaves) {
    FieldRefinementSettings rs = refine_settings();
    const auto first = refine_pass(8000, 1, false);
    const GuidingField built = GuidingField::build(kRefineBox, first, rs.field);
    FieldRefinement merging(built, first, 8000.0, rs);
    rs.merge_contrast = 0.f;
    FieldRefinement kept(built, first, 8000.0, rs);
    const auto second = refine_pass(16000, 2, false);
    const RefinementReport m = merging.add(second, 16000.0);
    const RefinementReport k = kept.add(second, 16000.0);
    EXPECT_GT(m.leaf_merges, 0);
    EXPECT_EQ(k.leaf_merges, 0);
    EXPECT_LT(merging.leaf_count(), kept.leaf_count());

    FieldRefinementSettings bounded = refine_settings();
    bounded.merge_contrast = 0.f;
    bounded.max_leaves = built.tree().leaf_count() + 3;
    FieldRefinement capped(built, first, 8000.0, bounded);
    for (uint64_t p = 2; p <= 4; ++p) capped.add(refine_pass(16000, p), 16000.0);
    EXPECT_LE(capped.leaf_count(), bounded.max_leaves);
    EXPECT_GT(capped.leaf_count(), built.tree().leaf_count());
}

// Leaves are updated in parallel, the tree changed in leaf order: the same field for one and two threads.
TEST(FieldRefinement, SameFieldForAnyThreadCount) {
    const FieldRefinementSettings rs = refine_settings();
    const auto first = refine_pass(8000, 1);
    const auto second = refine_pass(16000, 2);
    auto refine = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        FieldRefinement r(GuidingField::build(kRefineBox, first, rs.field), first, 8000.0, rs);
        r.add(second, 16000.0);
        return r.field();
    };
    EXPECT_TRUE(same_field(refine(1), refine(2)));
}

}  // namespace
}  // namespace volguide
