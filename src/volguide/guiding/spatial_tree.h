#pragma once
// The guiding field's spatial subdivision (docs/theory.md §5.3): a kd-tree over the media's bounds whose
// leaves hold at most `max_samples` training samples. A node splits at the sample mean of its
// axis of largest positional variance; when that does not separate the samples (or the variance
// is zero) it splits the longest axis at its midpoint; a node stops at `max_depth`.
//
// An optional mask restricts which samples count (towards max_samples and the split statistics):
// the others are only sorted into the leaves. Progressive training counts only samples that carry
// radiance, so the tree refines where light is, not where camera paths happen to scatter (an
// unguided walk puts vertices uniformly through thin fog; a light shaft holding a few percent of
// them would otherwise share its leaves with the dark room and leave them too few non-zero samples
// to fit).
//
// Queries: the leaf containing a point, and the leaves a ray segment crosses in order with their
// entry/exit distances (the guided distance sampler's bins, docs/theory.md §7.3). Building is sequential
// and order-preserving, so the tree is a pure function of the samples in their given order.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "volguide/core/bbox.h"

namespace volguide {

struct SpatialTreeSettings {
    int max_samples = 2000;  // docs/theory.md §15 ("leaf_samples")
    int max_depth = 32;
    // Subtrees of at least this many samples build their two halves concurrently. Only the build's
    // speed depends on it: the tree is the same for any value and any thread count.
    size_t parallel_min_samples = size_t(1) << 15;
};

// The build's split of a node by its samples (docs/theory.md §5.3): the mean of the counted samples on the
// axis of their largest positional variance, or the longest axis's midpoint when that mean does not
// separate them inside `box`; (3, 0) when neither is possible. `position(i)` and `counts(i)` read sample i
// of `idx`: the kd-tree's build and the refinement's leaf splits (field_refinement.h) use this one rule.
template <class Position, class Counts>
std::pair<int, float> mean_split(std::span<const uint32_t> idx, const BBox3f& box, Position position, Counts counts) {
    double mean[3] = {0, 0, 0}, sq[3] = {0, 0, 0}, n = 0;
    for (uint32_t i : idx) {
        if (!counts(i)) continue;
        n += 1;
        for (int a = 0; a < 3; ++a) {
            const double v = position(i)[a];
            mean[a] += v;
            sq[a] += v * v;
        }
    }
    int best = -1;
    double best_var = 0;
    for (int a = 0; a < 3; ++a) {
        mean[a] /= n;
        const double var = sq[a] / n - mean[a] * mean[a];
        if (var > best_var) best_var = var, best = a;
    }
    auto separates = [&](int a, float s) {
        bool below = false, above = false;
        for (uint32_t i : idx)
            if (counts(i)) (position(i)[a] < s ? below : above) = true;
        return below && above && s > box.lo[a] && s < box.hi[a];
    };
    if (best >= 0 && separates(best, float(mean[best]))) return {best, float(mean[best])};
    const Vec3f ext = box.extents();
    const int longest = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const float mid = 0.5f * (box.lo[longest] + box.hi[longest]);
    if (mid > box.lo[longest] && mid < box.hi[longest]) return {longest, mid};
    return {3, 0.f};
}

class SpatialTree {
public:
    // An empty tree: one leaf covering `bounds`.
    explicit SpatialTree(const BBox3f& bounds = BBox3f(Point3f(0.f), Point3f(0.f)));

    // Builds the tree over `bounds` from sample positions (points outside the bounds are clamped
    // into them). leaf_samples(i) then lists the indices of the samples in leaf i, in input order.
    // `counted` (empty = all count, else one flag per point) selects the samples that drive splits.
    static SpatialTree build(const BBox3f& bounds, std::span<const Point3f> points,
                             const SpatialTreeSettings& settings = {}, std::span<const uint8_t> counted = {});

    const BBox3f& bounds() const { return bounds_; }
    int leaf_count() const { return int(leaves_.size()); }
    int node_count() const { return int(nodes_.size()); }
    int depth() const { return depth_; }
    const BBox3f& leaf_bounds(int leaf) const { return leaves_[size_t(leaf)].box; }
    // Indices of the build samples that fell into `leaf` (empty for a tree not built from samples).
    std::span<const uint32_t> leaf_samples(int leaf) const;

    // The leaf containing p, or -1 outside the bounds. Points on a split plane go to the upper side.
    // The descent starts at p's cell of a uniform grid over the bounds (below), not at the root.
    int leaf_at(const Point3f& p) const {
        if (!bounds_.contains(p)) return -1;
        return leaf_below(jump_node(p), p);
    }
    // The leaf below `node` holding p (leaf_at's descent from a node whose region holds p).
    int leaf_below(uint32_t node, const Point3f& p) const {
        const float q[3] = {p.x, p.y, p.z};  // indexed by a node's axis without a branch
        while (!nodes_[node].is_leaf()) {
            const Node& n = nodes_[node];
            node = n.child + (q[n.axis] >= n.split ? 1u : 0u);
        }
        return int(nodes_[node].child);
    }
    // A cheap check of a guess: true only if leaf_at(p) == leaf (p in [lo, hi) of the leaf's box on
    // every axis: those are its ancestors' splits, and the descent goes up iff p >= split). False
    // for an invalid index and for points on the bounds' upper faces, which leaf_at still finds.
    bool holds_point(int leaf, const Point3f& p) const {
        if (leaf < 0 || leaf >= leaf_count()) return false;
        const BBox3f& b = leaves_[size_t(leaf)].box;
        return p.x >= b.lo.x && p.x < b.hi.x && p.y >= b.lo.y && p.y < b.hi.y && p.z >= b.lo.z && p.z < b.hi.z;
    }

    // Calls visit(leaf, t_enter, t_exit) for the leaves crossed by ray(t), t in (t0, t1), in order
    // of increasing t; the intervals are contiguous and cover the segment's overlap with the
    // bounds. visit returns false to stop early. Returns false if it was stopped.
    template <class Visit>
    bool traverse(const Ray& ray, float t0, float t1, Visit&& visit) const;

    // The same leaves as a pull iterator: next() yields them one at a time, so a caller that stops
    // early (the incremental distance sampler) pays only for the leaves it looked at. It walks
    // leaf to leaf by ropes (below) instead of a stack: the exit face of the current leaf's box,
    // then a short descent from that face's rope node with the exit point (its coordinate on the
    // exit axis set exactly to the face), ties broken by the ray's direction. The intervals are
    // contiguous, never empty, and cover the segment's overlap with the bounds (the last leaf is
    // extended to the bounds' exit); they equal traverse()'s up to float rounding of the crossing
    // distances (a little cheaper per leaf than the stack, bench_guiding
    // --benchmark_filter=LeafWalk; measured: see bench/RESULTS.md (issue 35)).
    class RayCursor {
    public:
        // `start` (may be -1): a guess of the leaf the segment starts in (the leaf of the vertex the ray
        // leaves from); taken without a descent from the root when the start point is strictly inside it.
        RayCursor(const SpatialTree& tree, const Ray& ray, float t0, float t1, int start = -1);
        // The next leaf and its interval; false after the last one. Inline: the distance walk takes one
        // step per leaf crossed.
        bool next(int& leaf, float& t_enter, float& t_exit);

    private:
        // The leaf below `node` holding p, a point of the ray: points on a split plane go to the side
        // the ray heads for (upper when parallel, as leaf_at).
        uint32_t descend(uint32_t node, const float p[3]) const;

        const SpatialTree* tree_;
        // Per axis (arrays: a node's axis indexes them without a branch): the origin, direction and its
        // inverse; whether the ray moves along the axis, heads up it (d >= 0: the side a point on a split
        // plane goes to), and which face of a box it leaves through (0 lower, 1 upper).
        float o_[3], d_[3], inv_d_[3];
        bool moving_[3], up_[3];
        bool finite_ = false;  // every inverse finite (no axis parallel, none so slow its inverse overflows)
        int exit_face_[3];
        int leaf_ = -1;  // the leaf to yield next; -1: none left
        float t_ = 0.f, t_end_ = 0.f;
    };

    // Rope of a leaf face (docs/theory.md §7.3's bins walk leaf to leaf): the deepest node whose region
    // holds everything just beyond that face, or kNoRope on the bounds. face = 2 axis + (1 for the
    // upper face).
    static constexpr uint32_t kNoRope = 0xffffffffu;
    uint32_t rope(int leaf, int face) const { return leaves_[size_t(leaf)].rope[face]; }

    // Flat storage, for serialization.
    struct Node {
        // Inner node: children at child and child + 1 (lower, upper), split plane on `axis`.
        // Leaf: axis = 3 and child = the leaf index.
        float split = 0.f;
        uint32_t child = 0;
        uint8_t axis = 3;
        bool is_leaf() const { return axis == 3; }
    };
    const std::vector<Node>& nodes() const { return nodes_; }
    // Rebuilds a tree from its nodes (leaf bounds are recomputed); throws std::invalid_argument
    // when the nodes do not form a valid tree.
    static SpatialTree from_nodes(const BBox3f& bounds, std::vector<Node> nodes);

private:
    void compute_leaf_bounds();  // and the ropes, and the jump grid
    void build_jump_grid();
    // The node leaf_at descends from for p in the bounds: its grid cell's.
    uint32_t jump_node(const Point3f& p) const {
        const Jump& g = jump_;
        const int x = std::min(int((p.x - bounds_.lo.x) * g.scale[0]), g.n[0] - 1);
        const int y = std::min(int((p.y - bounds_.lo.y) * g.scale[1]), g.n[1] - 1);
        const int z = std::min(int((p.z - bounds_.lo.z) * g.scale[2]), g.n[2] - 1);
        return g.node[(size_t(z) * size_t(g.n[1]) + size_t(y)) * size_t(g.n[0]) + size_t(x)];
    }

    // Point location's shortcut past the top of the tree: a uniform grid of about two cells per leaf,
    // each holding the deepest node whose region holds the cell with a margin (so that every point float
    // rounding maps into the cell lies below that node): the descent from it takes the same branches as
    // the one from the root, a few levels instead of the tree's depth, and at a large field's size a
    // cache miss or two instead of one per level.
    struct Jump {
        int n[3] = {1, 1, 1};
        float scale[3] = {0.f, 0.f, 0.f};  // cells per unit length
        std::vector<uint32_t> node{0u};
    };

    BBox3f bounds_;
    std::vector<Node> nodes_;
    // What the walk from leaf to leaf reads of a leaf, together (one 48-byte record: the box and its
    // six ropes, compute_leaf_bounds).
    struct LeafRecord {
        BBox3f box;
        uint32_t rope[6];
    };
    std::vector<LeafRecord> leaves_;
    Jump jump_;
    std::vector<uint32_t> sample_index_;  // samples grouped by leaf
    std::vector<uint32_t> leaf_offset_;   // leaf i: sample_index_[leaf_offset_[i] .. leaf_offset_[i + 1])
    int depth_ = 0;
};

inline uint32_t SpatialTree::RayCursor::descend(uint32_t node, const float p[3]) const {
    const Node* nodes = tree_->nodes_.data();
    while (!nodes[node].is_leaf()) {
        const Node& n = nodes[node];
        const float x = p[n.axis];
        const bool upper = x > n.split || (x == n.split && up_[n.axis]);
        node = n.child + (upper ? 1u : 0u);
    }
    return node;
}

inline bool SpatialTree::RayCursor::next(int& leaf, float& t_enter, float& t_exit) {
    // Leaves whose interval rounds to nothing (a corner or edge crossed exactly) are passed over.
    for (int guard = 0; leaf_ >= 0 && guard < 1 << 20; ++guard) {
        const LeafRecord& record = tree_->leaves_[size_t(leaf_)];
        const BBox3f& box = record.box;
        // The exit: the nearest face the ray leaves through (the first axis on a tie).
        const float face[3] = {exit_face_[0] ? box.hi.x : box.lo.x, exit_face_[1] ? box.hi.y : box.lo.y,
                               exit_face_[2] ? box.hi.z : box.lo.z};
        float exit = Infinity;
        int axis = -1;
        if (finite_) {  // every axis moves with a finite inverse: no distance is skipped or NaN
            const float t[3] = {(face[0] - o_[0]) * inv_d_[0], (face[1] - o_[1]) * inv_d_[1],
                                (face[2] - o_[2]) * inv_d_[2]};
            exit = t[0], axis = 0;
            if (t[1] < exit) exit = t[1], axis = 1;
            if (t[2] < exit) exit = t[2], axis = 2;
        } else {
            for (int a = 0; a < 3; ++a) {
                const float t = moving_[a] ? (face[a] - o_[a]) * inv_d_[a] : Infinity;
                if (t < exit) exit = t, axis = a;
            }
        }
        const int current = leaf_;
        const uint32_t rope = axis >= 0 ? record.rope[2 * axis + exit_face_[axis]] : kNoRope;
        const float t0 = t_;
        if (rope == kNoRope || !(exit < t_end_)) {
            // The last leaf: on to the end of the segment (the bounds' exit, up to rounding).
            leaf_ = -1;
            exit = t_end_;
        } else {
            exit = std::max(exit, t_);
            float p[3] = {o_[0] + d_[0] * exit, o_[1] + d_[1] * exit, o_[2] + d_[2] * exit};
            p[axis] = face[axis];  // exactly on the face
            leaf_ = int(tree_->nodes_[descend(rope, p)].child);
            t_ = exit;
        }
        if (exit > t0) {
            leaf = current;
            t_enter = t0;
            t_exit = exit;
            return true;
        }
    }
    leaf_ = -1;
    return false;
}

template <class Visit>
bool SpatialTree::traverse(const Ray& ray, float t0, float t1, Visit&& visit) const {
    float b0, b1;
    if (!bounds_.ray_intersect(ray, b0, b1)) return true;
    t0 = std::max(t0, b0);
    t1 = std::min(t1, b1);
    if (!(t0 < t1)) return true;
    const float inv_d[3] = {1.f / ray.d.x, 1.f / ray.d.y, 1.f / ray.d.z};
    struct Todo {
        uint32_t node;
        float t0, t1;
    };
    Todo stack[64];
    int top = 0;
    uint32_t node = 0;
    while (true) {
        const Node& n = nodes_[node];
        if (n.is_leaf()) {
            if (!visit(int(n.child), t0, t1)) return false;
            if (top == 0) return true;
            --top;
            node = stack[top].node;
            t0 = stack[top].t0;
            t1 = stack[top].t1;
            continue;
        }
        const int a = n.axis;
        const float t_split = (n.split - ray.o[a]) * inv_d[a];
        // Which side a point of the segment lies on; points on the plane belong to the upper child.
        auto upper_at = [&](float t) { return ray.o[a] + ray.d[a] * t >= n.split; };
        if (!(t_split > t0) || !(t_split < t1)) {  // no crossing inside (t0, t1) (or parallel)
            node = n.child + (upper_at(0.5f * (t0 + t1)) ? 1u : 0u);
            continue;
        }
        const bool near_upper = upper_at(0.5f * (t0 + t_split));
        const uint32_t near = n.child + (near_upper ? 1u : 0u), far = n.child + (near_upper ? 0u : 1u);
        stack[top++] = {far, t_split, t1};
        node = near;
        t1 = t_split;
    }
}

}  // namespace volguide
