// LeafGroups (guiding/leaf_groups.h): leaves with the same estimates become one group,
// leaves whose estimates differ stay apart, every group's tables stay within the tolerance of each
// of its leaves', a group finds the leaf holding a point, and the groups' tree covers the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "support/guiding_leaf_fixtures.h"
#include "support/turning_light_field.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/integrators/guided/walk/distance_bins.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const BBox3f kGroupsBox = kTurningLightBox;

SpatialTree test_tree(int max_samples) {
    std::vector<Point3f> points;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(11, 0, uint64_t(i));
        points.emplace_back(2.f * s.next_1d(), s.next_1d(), s.next_1d());
    }
    SpatialTreeSettings settings;
    settings.max_samples = max_samples;
    return SpatialTree::build(kGroupsBox, points, settings);
}

// Hand-made leaves on the tree: `kind(centre)` picks one of two shapes for each leaf.
template <class Kind>
GuidingField field_of(const SpatialTree& tree, Kind&& kind) {
    std::vector<GuidingLeaf> leaves;
    for (int l = 0; l < tree.leaf_count(); ++l) {
        GuidingLeaf leaf = kind(tree.leaf_bounds(l).center()) ? one_lobe_leaf() : multi_lobe_leaf();
        leaves.push_back(leaf);
    }
    return GuidingField(tree, std::move(leaves));
}

// A fitted field: every leaf differs a little from its neighbours.
GuidingField fitted_field() {
    return turning_light_field(5.f, 0.5f, 500, 4);
}

// The fine leaf's channel-average estimates against its group's, at a point and a direction.
struct Pair {
    bool valid_leaf, valid_group;
    float Li_leaf, L_leaf, Li_group, L_group;
};
Pair lookup_both(const GuidingField& field, const LeafEstimates& est, const LeafGroups& groups,
                 const Point3f& p, const Vec3f& w) {
    const LeafEstimates::Direction d = est.prepare(w);
    Pair r{};
    Color3 Li, L;
    r.valid_leaf = est.lookup(field.tree().leaf_at(p), d, Li, L);
    r.Li_leaf = r.valid_leaf ? Li.average() : 0.f;
    r.L_leaf = r.valid_leaf ? L.average() : 0.f;
    r.valid_group = groups.lookup(groups.tree().leaf_at(p), d, r.Li_group, r.L_group);
    return r;
}

// At `count` random points and directions, each group reads what its leaf reads, within `rel` of
// max(value, floor) (16-bit rounding of merged tables of identical leaves).
void expect_groups_read_their_leaves(const GuidingField& field, const LeafEstimates& est,
                                      const LeafGroups& groups, int count, uint64_t seed, float rel,
                                      float floor) {
    for (int i = 0; i < count; ++i) {
        Sampler s(seed, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Pair r = lookup_both(field, est, groups, p, warp::square_to_uniform_sphere(s.next_2d()));
        ASSERT_TRUE(r.valid_leaf && r.valid_group);
        EXPECT_NEAR(r.Li_group, r.Li_leaf, rel * std::max(r.Li_leaf, floor));
        EXPECT_NEAR(r.L_group, r.L_leaf, rel * std::max(r.L_leaf, floor));
    }
}

}  // namespace

TEST(LeafGroups, IdenticalLeavesBecomeOneGroup) {
    const SpatialTree tree = test_tree(300);
    ASSERT_GT(tree.leaf_count(), 32);
    const GuidingField field = field_of(tree, [](const Point3f&) { return true; });
    const InscatterCache cache(field, hg_phase_vmm(0.3f));
    const LeafEstimates est(field, cache, 16);
    const LeafGroups groups(tree, est, leaf_extents(tree), 0.f);
    EXPECT_EQ(groups.group_count(), 1);
    expect_groups_read_their_leaves(field, est, groups, 200, 2, 1e-4f, 1e-3f);
}

// Two shapes, split by a plane that is not a kd split: no group mixes them (every point reads its
// own leaf's shape from its group), yet each side merges.
TEST(LeafGroups, DifferentLeavesStayApart) {
    const SpatialTree tree = test_tree(300);
    const GuidingField field = field_of(tree, [](const Point3f& c) { return c.x + 0.5f * c.y < 1.1f; });
    const InscatterCache cache(field, hg_phase_vmm(0.3f));
    const LeafEstimates est(field, cache, 16);
    const LeafGroups groups(tree, est, leaf_extents(tree), 0.05f);
    EXPECT_GE(groups.group_count(), 2);
    EXPECT_LT(groups.group_count(), tree.leaf_count() / 2);
    expect_groups_read_their_leaves(field, est, groups, 2000, 3, 1e-3f, 1e-2f);
}

// A fitted field: groups merge leaves, more of them as the tolerance grows (tolerance 0 keeps
// every valid leaf apart), and a group's estimates differ from each of its leaves' by at most the
// tolerance on average over directions (the merge rule bounds the mean spread over the texels).
TEST(LeafGroups, GroupsStayWithinTheTolerance) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates est(field, cache, 16);
    const std::vector<float> extents = leaf_extents(field.tree());
    const int valid =
        int(std::count_if(field.leaves().begin(), field.leaves().end(), [](const GuidingLeaf& l) { return l.valid; }));
    ASSERT_GT(valid, 16);
    EXPECT_GE(LeafGroups(field.tree(), est, extents, 0.f).group_count(), valid);
    const float tolerance = 0.3f;
    const int at_01 = LeafGroups(field.tree(), est, extents, 0.1f).group_count();
    const LeafGroups groups(field.tree(), est, extents, tolerance);
    EXPECT_LT(groups.group_count(), at_01);
    EXPECT_LE(at_01, field.tree().leaf_count());
    double spread_i = 0.0, spread_l = 0.0;
    int n = 0;
    for (int i = 0; i < 4000; ++i) {
        Sampler s(4, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Pair r = lookup_both(field, est, groups, p, warp::square_to_uniform_sphere(s.next_2d()));
        ASSERT_EQ(r.valid_leaf, r.valid_group);
        if (!r.valid_leaf) continue;
        spread_i += std::abs(r.Li_group - r.Li_leaf) / std::max(r.Li_group, r.Li_leaf);
        spread_l += std::abs(r.L_group - r.L_leaf) / std::max(r.L_group, r.L_leaf);
        ++n;
    }
    ASSERT_GT(n, 1000);
    EXPECT_LE(spread_i / n, tolerance);
    EXPECT_LE(spread_l / n, tolerance);
    std::cout << "groups at tolerance 0.1 / 0.3: " << at_01 << " / " << groups.group_count() << " of "
              << field.tree().leaf_count() << " leaves; mean relative difference group vs leaf: L~_i "
              << spread_i / n << ", L~ " << spread_l / n << "\n";
}

// Groups partition the field's bounds; a group finds the field's leaf at any of its points; its
// extent is the largest of its leaves'.
TEST(LeafGroups, GroupsHoldTheirLeaves) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates est(field, cache, 16);
    const std::vector<float> extents = leaf_extents(field.tree());
    const LeafGroups groups(field.tree(), est, extents, 0.3f);
    EXPECT_EQ(groups.tree().bounds().lo, field.tree().bounds().lo);
    EXPECT_EQ(groups.tree().bounds().hi, field.tree().bounds().hi);
    for (int i = 0; i < 4000; ++i) {
        Sampler s(5, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const int group = groups.tree().leaf_at(p);
        ASSERT_GE(group, 0);
        const int leaf = field.tree().leaf_at(p);
        EXPECT_EQ(groups.fine_leaf(group, p), leaf);
        EXPECT_GE(groups.extent(group), extents[size_t(leaf)]);
        EXPECT_TRUE(groups.tree().leaf_bounds(group).contains(p));
    }
}

TEST(LeafGroups, NeedTheTables) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates exact(field, cache, 0);
    EXPECT_THROW(LeafGroups(field.tree(), exact, leaf_extents(field.tree()), 0.1f), std::invalid_argument);
}
