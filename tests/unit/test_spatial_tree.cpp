// The guiding kd-tree (docs/theory.md §5.3): leaves hold at most max_samples samples, leaves tile the
// bounds, point lookup agrees with the build's partition, ray traversal yields contiguous ordered
// intervals that agree with point lookup, and rebuilding from the node array is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "volguide/core/parallel.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/spatial_tree.h"

using namespace volguide;

namespace {

const BBox3f kBounds(Point3f(-2.f, -1.f, 0.f), Point3f(2.f, 3.f, 1.f));

// Clustered points: a dense blob, a plane of identical z, and uniform background.
std::vector<Point3f> points(int n, uint64_t seed) {
    std::vector<Point3f> out;
    for (int i = 0; i < n; ++i) {
        Sampler s(seed, 0, uint64_t(i));
        const float kind = s.next_1d();
        const Point3f u(s.next_1d(), s.next_1d(), s.next_1d());
        const Vec3f ext = kBounds.extents();
        if (kind < 0.4f)
            out.push_back(Point3f(0.5f, 1.f, 0.3f) + (u - Point3f(0.5f)) * 0.2f);
        else if (kind < 0.6f)
            out.push_back(Point3f(kBounds.lo.x + u.x * ext.x, kBounds.lo.y + u.y * ext.y, 0.75f));
        else
            out.push_back(kBounds.lo + Vec3f(u.x * ext.x, u.y * ext.y, u.z * ext.z));
    }
    return out;
}

double volume(const BBox3f& b) {
    const Vec3f e = b.extents();
    return double(e.x) * e.y * e.z;
}

}  // namespace

TEST(SpatialTree, LeavesRespectTheSampleLimitAndTileTheBounds) {
    const auto pts = points(20000, 1);
    SpatialTreeSettings settings;
    settings.max_samples = 500;
    SpatialTree tree = SpatialTree::build(kBounds, pts, settings);
    EXPECT_GT(tree.leaf_count(), 40);
    double vol = 0;
    size_t total = 0;
    for (int l = 0; l < tree.leaf_count(); ++l) {
        EXPECT_LE(tree.leaf_samples(l).size(), 500u) << "leaf " << l;
        total += tree.leaf_samples(l).size();
        vol += volume(tree.leaf_bounds(l));
        for (uint32_t i : tree.leaf_samples(l)) {
            EXPECT_EQ(tree.leaf_at(pts[i]), l) << "sample " << i;
            EXPECT_TRUE(tree.leaf_bounds(l).contains(pts[i]));
        }
    }
    EXPECT_EQ(total, pts.size());
    EXPECT_NEAR(vol, volume(kBounds), 1e-4 * volume(kBounds));
    EXPECT_EQ(tree.leaf_at(Point3f(5.f, 0.f, 0.5f)), -1);
}

// holds_point(l, p) certifies leaf_at(p) == l (the walk guide reuses the distance decision's leaf for
// the direction decision at the same vertex and must get leaf_at's answer): checked for points
// snapped onto split planes and the bounds' faces, where the two could disagree.
TEST(SpatialTree, HoldsPointImpliesLeafAt) {
    const auto pts = points(20000, 4);
    SpatialTreeSettings settings;
    settings.max_samples = 300;
    const SpatialTree tree = SpatialTree::build(kBounds, pts, settings);
    int held = 0;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(9, 0, uint64_t(i));
        const int guess = int(s.next_1d() * float(tree.leaf_count()));
        const BBox3f& b = tree.leaf_bounds(std::min(guess, tree.leaf_count() - 1));
        // A point of the guessed leaf's box, some coordinates snapped to its faces.
        Point3f p;
        for (int a = 0; a < 3; ++a) {
            const float u = s.next_1d(), lo = a == 0 ? b.lo.x : a == 1 ? b.lo.y : b.lo.z,
                        hi = a == 0 ? b.hi.x : a == 1 ? b.hi.y : b.hi.z;
            const float v = u < 0.2f ? lo : u < 0.4f ? hi : u < 0.5f ? std::nextafter(hi, lo) : lo + (hi - lo) * s.next_1d();
            (a == 0 ? p.x : a == 1 ? p.y : p.z) = v;
        }
        for (int l : {guess, guess - 1, guess + 1, -1, tree.leaf_count()})
            if (tree.holds_point(l, p)) {
                ++held;
                ASSERT_EQ(tree.leaf_at(p), l) << "point " << i;
            }
    }
    EXPECT_GT(held, 1000);
}

// leaf_at descends from its point's cell of the jump grid: the same leaf as the descent from the root
// for points on leaf faces and split planes, just off them, on the bounds' faces and inside, in trees of
// any size (one leaf to thousands) and off-centre bounds far from the origin.
TEST(SpatialTree, JumpGridDescentIsTheRootDescent) {
    for (int max_samples : {100000, 2000, 40, 3}) {
        for (const Vec3f& shift : {Vec3f(0.f), Vec3f(4000.f, -250.f, 17.f)}) {
            std::vector<Point3f> pts = points(20000, 5);
            for (Point3f& q : pts) q = q + shift;
            const BBox3f bounds(kBounds.lo + shift, kBounds.hi + shift);
            SpatialTreeSettings settings;
            settings.max_samples = max_samples;
            const SpatialTree tree = SpatialTree::build(bounds, pts, settings);
            for (int i = 0; i < 20000; ++i) {
                Sampler s(13, uint64_t(max_samples), uint64_t(i));
                const BBox3f& b = tree.leaf_bounds(std::min(int(s.next_1d() * float(tree.leaf_count())),
                                                            tree.leaf_count() - 1));
                Point3f p;
                for (int a = 0; a < 3; ++a) {
                    const float u = s.next_1d(), lo = a == 0 ? b.lo.x : a == 1 ? b.lo.y : b.lo.z,
                                hi = a == 0 ? b.hi.x : a == 1 ? b.hi.y : b.hi.z;
                    const float v = u < 0.2f   ? lo
                                    : u < 0.4f ? hi
                                    : u < 0.5f ? std::nextafter(lo, -INFINITY)
                                    : u < 0.6f ? std::nextafter(hi, INFINITY)
                                               : lo + (hi - lo) * s.next_1d();
                    (a == 0 ? p.x : a == 1 ? p.y : p.z) = v;
                }
                const int expected = bounds.contains(p) ? tree.leaf_below(0u, p) : -1;
                ASSERT_EQ(tree.leaf_at(p), expected) << max_samples << " point " << i;
            }
        }
    }
}

// Only the counted samples drive splits: uncounted ones are sorted into the leaves (every sample
// lands in exactly the leaf containing it) but neither reach max_samples nor move the split means.
// Counting only the blob's samples refines the blob and leaves the uniform background coarse.
TEST(SpatialTree, OnlyCountedSamplesDriveSplits) {
    const auto pts = points(20000, 4);
    std::vector<uint8_t> counted(pts.size());
    const BBox3f blob(Point3f(0.39f, 0.89f, 0.19f), Point3f(0.61f, 1.11f, 0.41f));
    size_t in_blob = 0;
    for (size_t i = 0; i < pts.size(); ++i) in_blob += counted[i] = blob.contains(pts[i]);
    SpatialTreeSettings settings;
    settings.max_samples = 200;
    const SpatialTree all = SpatialTree::build(kBounds, pts, settings);
    const SpatialTree masked = SpatialTree::build(kBounds, pts, settings, counted);
    size_t total = 0;
    int counted_leaves = 0, coarse_leaves = 0;
    for (int l = 0; l < masked.leaf_count(); ++l) {
        size_t c = 0;
        for (uint32_t i : masked.leaf_samples(l)) {
            EXPECT_EQ(masked.leaf_at(pts[i]), l);
            c += counted[i];
        }
        EXPECT_LE(c, 200u) << "leaf " << l;
        total += masked.leaf_samples(l).size();
        counted_leaves += c > 0;
        coarse_leaves += masked.leaf_samples(l).size() > 200u;
    }
    EXPECT_EQ(total, pts.size());
    EXPECT_GE(counted_leaves, int(in_blob / 200));  // the blob is refined to the limit
    EXPECT_GT(coarse_leaves, 0);                     // the background is not
    EXPECT_LT(masked.leaf_count(), all.leaf_count());
    // All flags set is the unmasked build.
    const std::vector<uint8_t> ones(pts.size(), 1);
    const SpatialTree same = SpatialTree::build(kBounds, pts, settings, ones);
    ASSERT_EQ(same.node_count(), all.node_count());
    for (int n = 0; n < all.node_count(); ++n) {
        EXPECT_EQ(same.nodes()[size_t(n)].split, all.nodes()[size_t(n)].split);
        EXPECT_EQ(same.nodes()[size_t(n)].axis, all.nodes()[size_t(n)].axis);
    }
    EXPECT_THROW(SpatialTree::build(kBounds, pts, settings, std::vector<uint8_t>(3, 1)), std::invalid_argument);
}

TEST(SpatialTree, IdenticalPointsStopAtTheDepthCapOrTheFloatLimit) {
    std::vector<Point3f> same(100, Point3f(0.1f, 0.2f, 0.3f));
    SpatialTreeSettings settings;
    settings.max_samples = 10;
    settings.max_depth = 12;
    SpatialTree tree = SpatialTree::build(kBounds, same, settings);
    EXPECT_LE(tree.depth(), 12);
    const int leaf = tree.leaf_at(same[0]);
    EXPECT_EQ(tree.leaf_samples(leaf).size(), 100u);
}

TEST(SpatialTree, BuildIsAPureFunctionOfTheSamples) {
    const auto pts = points(5000, 2);
    SpatialTreeSettings settings;
    settings.max_samples = 100;
    SpatialTree a = SpatialTree::build(kBounds, pts, settings), b = SpatialTree::build(kBounds, pts, settings);
    ASSERT_EQ(a.nodes().size(), b.nodes().size());
    for (size_t i = 0; i < a.nodes().size(); ++i) {
        EXPECT_EQ(a.nodes()[i].split, b.nodes()[i].split);
        EXPECT_EQ(a.nodes()[i].child, b.nodes()[i].child);
        EXPECT_EQ(a.nodes()[i].axis, b.nodes()[i].axis);
    }
}

// Large subtrees build their halves concurrently and splice them in the sequential build's order:
// splicing at every split of 64 samples or more, on one thread and on two, gives the arrays of the
// sequential build exactly (nodes, leaf numbering, samples per leaf), masked or not.
TEST(SpatialTree, ConcurrentBuildIsTheSequentialBuild) {
    const auto pts = points(60000, 5);
    std::vector<uint8_t> counted(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) counted[i] = uint8_t(i % 3 != 0);
    for (const bool masked : {false, true}) {
        SCOPED_TRACE(masked ? "masked" : "all counted");
        const std::span<const uint8_t> mask = masked ? std::span<const uint8_t>(counted) : std::span<const uint8_t>();
        SpatialTreeSettings sequential;
        sequential.max_samples = 50;
        sequential.parallel_min_samples = pts.size() + 1;
        const SpatialTree ref = SpatialTree::build(kBounds, pts, sequential, mask);
        ASSERT_GT(ref.leaf_count(), 500);
        SpatialTreeSettings concurrent = sequential;
        concurrent.parallel_min_samples = 64;
        for (int threads : {1, 2}) {
            SCOPED_TRACE(threads);
            tbb::task_arena arena(threads);
            const SpatialTree t =
                arena_execute(arena, [&] { return SpatialTree::build(kBounds, pts, concurrent, mask); });
            ASSERT_EQ(t.nodes().size(), ref.nodes().size());
            for (size_t i = 0; i < t.nodes().size(); ++i) {
                ASSERT_EQ(t.nodes()[i].split, ref.nodes()[i].split) << "node " << i;
                ASSERT_EQ(t.nodes()[i].child, ref.nodes()[i].child) << "node " << i;
                ASSERT_EQ(t.nodes()[i].axis, ref.nodes()[i].axis) << "node " << i;
            }
            ASSERT_EQ(t.leaf_count(), ref.leaf_count());
            for (int l = 0; l < t.leaf_count(); ++l) {
                const auto a = t.leaf_samples(l), b = ref.leaf_samples(l);
                ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "leaf " << l;
            }
            EXPECT_EQ(t.depth(), ref.depth());
        }
    }
}

TEST(SpatialTree, TraversalIsContiguousOrderedAndAgreesWithPointLookup) {
    const auto pts = points(20000, 3);
    SpatialTreeSettings settings;
    settings.max_samples = 200;
    SpatialTree tree = SpatialTree::build(kBounds, pts, settings);
    for (int r = 0; r < 2000; ++r) {
        Sampler s(4, 0, uint64_t(r));
        // Origins inside and outside the bounds; some axis-parallel directions.
        Point3f o(-3.f + 6.f * s.next_1d(), -2.f + 6.f * s.next_1d(), -0.5f + 2.f * s.next_1d());
        Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
        if (r % 10 == 0) d = Vec3f(r % 20 == 0 ? 1.f : 0.f, r % 20 == 0 ? 0.f : -1.f, 0.f);
        if (r % 7 == 0) o = pts[size_t(r)];  // starting exactly at a sample
        const Ray ray(o, d);
        const float t0 = (r % 3 == 0) ? 0.5f : 0.f, t1 = (r % 5 == 0) ? 2.f : Infinity;
        float expect_start, expect_end;
        const bool hits = kBounds.ray_intersect(ray, expect_start, expect_end) &&
                          std::max(expect_start, t0) < std::min(expect_end, t1);
        float prev_end = NAN;
        int count = 0;
        tree.traverse(ray, t0, t1, [&](int leaf, float ta, float tb) {
            EXPECT_LT(ta, tb) << "ray " << r;
            if (count == 0)
                EXPECT_FLOAT_EQ(ta, std::max(expect_start, t0)) << "ray " << r;
            else
                EXPECT_EQ(ta, prev_end) << "ray " << r << " gap or overlap at interval " << count;
            // The interval's midpoint lies in the reported leaf (away from its faces).
            if (tb - ta > 1e-4f) {
                EXPECT_EQ(tree.leaf_at(ray(0.5f * (ta + tb))), leaf) << "ray " << r;
            }
            prev_end = tb;
            ++count;
            return true;
        });
        if (hits) {
            EXPECT_GT(count, 0) << "ray " << r;
            EXPECT_FLOAT_EQ(prev_end, std::min(expect_end, t1)) << "ray " << r;
        } else {
            EXPECT_EQ(count, 0) << "ray " << r;
        }
    }
}

TEST(SpatialTree, TraversalStopsWhenAsked) {
    SpatialTreeSettings settings;
    settings.max_samples = 50;
    SpatialTree tree = SpatialTree::build(kBounds, points(5000, 5), settings);
    int visits = 0;
    const bool finished = tree.traverse(Ray(Point3f(-3.f, 1.f, 0.3f), Vec3f(1.f, 0.f, 0.f)), 0.f, Infinity,
                                        [&](int, float, float) { return ++visits < 2; });
    EXPECT_FALSE(finished);
    EXPECT_EQ(visits, 2);
}

TEST(SpatialTree, RebuiltFromNodesIsIdenticalAndBadNodesAreRejected) {
    SpatialTreeSettings settings;
    settings.max_samples = 100;
    SpatialTree tree = SpatialTree::build(kBounds, points(5000, 6), settings);
    SpatialTree copy = SpatialTree::from_nodes(kBounds, tree.nodes());
    ASSERT_EQ(copy.leaf_count(), tree.leaf_count());
    for (int i = 0; i < 1000; ++i) {
        Sampler s(7, 0, uint64_t(i));
        const Point3f p = kBounds.lo + Vec3f(s.next_1d() * 4.f, s.next_1d() * 4.f, s.next_1d());
        EXPECT_EQ(copy.leaf_at(p), tree.leaf_at(p));
    }
    auto bad = tree.nodes();
    bad[0].child = 0;  // a cycle
    EXPECT_THROW(SpatialTree::from_nodes(kBounds, bad), std::invalid_argument);
    bad = tree.nodes();
    bad[0].split = 10.f;  // outside the bounds
    EXPECT_THROW(SpatialTree::from_nodes(kBounds, bad), std::invalid_argument);
    bad = tree.nodes();
    bad[0].axis = 7;
    EXPECT_THROW(SpatialTree::from_nodes(kBounds, bad), std::invalid_argument);
    bad = tree.nodes();
    bad.pop_back();  // a dangling child
    EXPECT_THROW(SpatialTree::from_nodes(kBounds, bad), std::invalid_argument);
}

// The pull cursor yields exactly traverse()'s sequence (leaf and interval, bit for bit).
TEST(SpatialTree, RayCursorYieldsTheTraversalSequence) {
    const auto pts = points(20000, 6);
    SpatialTreeSettings settings;
    settings.max_samples = 150;
    SpatialTree tree = SpatialTree::build(kBounds, pts, settings);
    int total = 0;
    for (int r = 0; r < 2000; ++r) {
        Sampler s(7, 0, uint64_t(r));
        const Point3f o(-3.f + 6.f * s.next_1d(), -2.f + 6.f * s.next_1d(), -0.5f + 2.f * s.next_1d());
        Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
        if (r % 10 == 0) d = Vec3f(0.f, 0.f, 1.f);
        const Ray ray(o, d);
        const float t0 = (r % 3 == 0) ? 0.5f : 0.f, t1 = (r % 5 == 0) ? 2.f : Infinity;
        struct Step {
            int leaf;
            float a, b;
        };
        std::vector<Step> expected, got;
        tree.traverse(ray, t0, t1, [&](int leaf, float a, float b) {
            expected.push_back({leaf, a, b});
            return true;
        });
        SpatialTree::RayCursor cursor(tree, ray, t0, t1);
        Step st;
        while (cursor.next(st.leaf, st.a, st.b)) got.push_back(st);
        ASSERT_EQ(got.size(), expected.size()) << "ray " << r;
        for (size_t i = 0; i < got.size(); ++i) {
            EXPECT_EQ(got[i].leaf, expected[i].leaf) << "ray " << r << " step " << i;
            EXPECT_EQ(got[i].a, expected[i].a);
            EXPECT_EQ(got[i].b, expected[i].b);
        }
        total += int(got.size());
    }
    EXPECT_GT(total, 2000);  // the rays cross many leaves (2373 measured)
}
