// DistanceRegions (guiding/distance_regions.h): leaves with the same estimates become one region,
// leaves whose estimates differ stay apart, every region's tables stay within the tolerance of each
// of its leaves', a region finds the leaf holding a point, and the regions' tree covers the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "support/guiding_leaf_fixtures.h"
#include "support/turning_light_field.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/distance_regions.h"
#include "volguide/integrators/guided/walk/distance_bins.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const BBox3f kBox = kTurningLightBox;

SpatialTree test_tree(int max_samples) {
    std::vector<Point3f> points;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(11, 0, uint64_t(i));
        points.emplace_back(2.f * s.next_1d(), s.next_1d(), s.next_1d());
    }
    SpatialTreeSettings settings;
    settings.max_samples = max_samples;
    return SpatialTree::build(kBox, points, settings);
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

// The fine leaf's channel-average estimates against its region's, at a point and a direction.
struct Pair {
    bool valid_leaf, valid_region;
    float Li_leaf, L_leaf, Li_region, L_region;
};
Pair lookup_both(const GuidingField& field, const LeafEstimates& est, const DistanceRegions& regions,
                 const Point3f& p, const Vec3f& w) {
    const LeafEstimates::Direction d = est.prepare(w);
    Pair r{};
    Color3 Li, L;
    r.valid_leaf = est.lookup(field.tree().leaf_at(p), d, Li, L);
    r.Li_leaf = r.valid_leaf ? Li.average() : 0.f;
    r.L_leaf = r.valid_leaf ? L.average() : 0.f;
    r.valid_region = regions.lookup(regions.tree().leaf_at(p), d, r.Li_region, r.L_region);
    return r;
}

// At `count` random points and directions, each region reads what its leaf reads, within `rel` of
// max(value, floor) (16-bit rounding of merged tables of identical leaves).
void expect_regions_read_their_leaves(const GuidingField& field, const LeafEstimates& est,
                                      const DistanceRegions& regions, int count, uint64_t seed, float rel,
                                      float floor) {
    for (int i = 0; i < count; ++i) {
        Sampler s(seed, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Pair r = lookup_both(field, est, regions, p, warp::square_to_uniform_sphere(s.next_2d()));
        ASSERT_TRUE(r.valid_leaf && r.valid_region);
        EXPECT_NEAR(r.Li_region, r.Li_leaf, rel * std::max(r.Li_leaf, floor));
        EXPECT_NEAR(r.L_region, r.L_leaf, rel * std::max(r.L_leaf, floor));
    }
}

}  // namespace

TEST(DistanceRegions, IdenticalLeavesBecomeOneRegion) {
    const SpatialTree tree = test_tree(300);
    ASSERT_GT(tree.leaf_count(), 32);
    const GuidingField field = field_of(tree, [](const Point3f&) { return true; });
    const InscatterCache cache(field, hg_phase_vmm(0.3f));
    const LeafEstimates est(field, cache, 16);
    const DistanceRegions regions(tree, est, leaf_extents(tree), 0.f);
    EXPECT_EQ(regions.region_count(), 1);
    expect_regions_read_their_leaves(field, est, regions, 200, 2, 1e-4f, 1e-3f);
}

// Two shapes, split by a plane that is not a kd split: no region mixes them (every point reads its
// own leaf's shape from its region), yet each side merges.
TEST(DistanceRegions, DifferentLeavesStayApart) {
    const SpatialTree tree = test_tree(300);
    const GuidingField field = field_of(tree, [](const Point3f& c) { return c.x + 0.5f * c.y < 1.1f; });
    const InscatterCache cache(field, hg_phase_vmm(0.3f));
    const LeafEstimates est(field, cache, 16);
    const DistanceRegions regions(tree, est, leaf_extents(tree), 0.05f);
    EXPECT_GE(regions.region_count(), 2);
    EXPECT_LT(regions.region_count(), tree.leaf_count() / 2);
    expect_regions_read_their_leaves(field, est, regions, 2000, 3, 1e-3f, 1e-2f);
}

// A fitted field: regions merge leaves, more of them as the tolerance grows (tolerance 0 keeps
// every valid leaf apart), and a region's estimates differ from each of its leaves' by at most the
// tolerance on average over directions (the merge rule bounds the mean spread over the texels).
TEST(DistanceRegions, RegionsStayWithinTheTolerance) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates est(field, cache, 16);
    const std::vector<float> extents = leaf_extents(field.tree());
    const int valid =
        int(std::count_if(field.leaves().begin(), field.leaves().end(), [](const GuidingLeaf& l) { return l.valid; }));
    ASSERT_GT(valid, 16);
    EXPECT_GE(DistanceRegions(field.tree(), est, extents, 0.f).region_count(), valid);
    const float tolerance = 0.3f;
    const int at_01 = DistanceRegions(field.tree(), est, extents, 0.1f).region_count();
    const DistanceRegions regions(field.tree(), est, extents, tolerance);
    EXPECT_LT(regions.region_count(), at_01);
    EXPECT_LE(at_01, field.tree().leaf_count());
    double spread_i = 0.0, spread_l = 0.0;
    int n = 0;
    for (int i = 0; i < 4000; ++i) {
        Sampler s(4, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Pair r = lookup_both(field, est, regions, p, warp::square_to_uniform_sphere(s.next_2d()));
        ASSERT_EQ(r.valid_leaf, r.valid_region);
        if (!r.valid_leaf) continue;
        spread_i += std::abs(r.Li_region - r.Li_leaf) / std::max(r.Li_region, r.Li_leaf);
        spread_l += std::abs(r.L_region - r.L_leaf) / std::max(r.L_region, r.L_leaf);
        ++n;
    }
    ASSERT_GT(n, 1000);
    EXPECT_LE(spread_i / n, tolerance);
    EXPECT_LE(spread_l / n, tolerance);
    std::cout << "regions at tolerance 0.1 / 0.3: " << at_01 << " / " << regions.region_count() << " of "
              << field.tree().leaf_count() << " leaves; mean relative difference region vs leaf: L~_i "
              << spread_i / n << ", L~ " << spread_l / n << "\n";
}

// Regions partition the field's bounds; a region finds the field's leaf at any of its points; its
// extent is the largest of its leaves'.
TEST(DistanceRegions, RegionsHoldTheirLeaves) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates est(field, cache, 16);
    const std::vector<float> extents = leaf_extents(field.tree());
    const DistanceRegions regions(field.tree(), est, extents, 0.3f);
    EXPECT_EQ(regions.tree().bounds().lo, field.tree().bounds().lo);
    EXPECT_EQ(regions.tree().bounds().hi, field.tree().bounds().hi);
    for (int i = 0; i < 4000; ++i) {
        Sampler s(5, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const int region = regions.tree().leaf_at(p);
        ASSERT_GE(region, 0);
        const int leaf = field.tree().leaf_at(p);
        EXPECT_EQ(regions.fine_leaf(region, p), leaf);
        EXPECT_GE(regions.extent(region), extents[size_t(leaf)]);
        EXPECT_TRUE(regions.tree().leaf_bounds(region).contains(p));
    }
}

TEST(DistanceRegions, NeedTheTables) {
    const GuidingField field = fitted_field();
    const InscatterCache cache(field, hg_phase_vmm(0.5f));
    const LeafEstimates exact(field, cache, 0);
    EXPECT_THROW(DistanceRegions(field.tree(), exact, leaf_extents(field.tree()), 0.1f), std::invalid_argument);
}
