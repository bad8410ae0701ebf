#include "volguide/guiding/spatial_tree.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/parallel.h"

namespace volguide {

SpatialTree::SpatialTree(const BBox3f& bounds) : bounds_(bounds) {
    nodes_.push_back(Node{0.f, 0u, 3});
    leaf_offset_ = {0u, 0u};
    compute_leaf_bounds();
}

std::span<const uint32_t> SpatialTree::leaf_samples(int leaf) const {
    if (leaf_offset_.size() != leaves_.size() + 1) return {};
    return {sample_index_.data() + leaf_offset_[size_t(leaf)], leaf_offset_[size_t(leaf) + 1] - leaf_offset_[size_t(leaf)]};
}

namespace {

// Builds a subtree into its own arrays, in the order of a depth-first build: a split appends its two
// children, then the lower child's subtree, then the upper's; leaves are numbered and their samples
// appended in that order. Subtrees of at least parallel_min_samples samples build their two halves
// concurrently into two Builders and splice them in lower-then-upper order, which gives exactly the
// arrays of the sequential build (the same tree for any thread count).
struct Builder {
    std::span<const Point3f> points;
    std::span<const uint8_t> counted;  // empty: every point counts
    const SpatialTreeSettings* settings;
    std::vector<SpatialTree::Node> nodes{SpatialTree::Node{}};  // nodes[0]: this subtree's root
    std::vector<uint32_t> order;                                // sample indices, grouped by leaf
    std::vector<uint32_t> leaf_offset{0u};

    Builder(std::span<const Point3f> p, std::span<const uint8_t> c, const SpatialTreeSettings& s)
        : points(p), counted(c), settings(&s) {}

    // Chooses the split of `idx` inside `box`: (axis, position), or axis 3 for "make a leaf".
    std::pair<int, float> choose_split(const std::vector<uint32_t>& idx, const BBox3f& box) const {
        return mean_split(idx, box, [&](uint32_t i) -> const Point3f& { return points[i]; },
                          [&](uint32_t i) { return counts(i); });
    }

    bool counts(uint32_t i) const { return counted.empty() || counted[i] != 0; }

    void make_leaf(uint32_t node, const std::vector<uint32_t>& idx) {
        nodes[node] = SpatialTree::Node{0.f, uint32_t(leaf_offset.size() - 1), 3};
        order.insert(order.end(), idx.begin(), idx.end());
        leaf_offset.push_back(uint32_t(order.size()));
    }

    void build(uint32_t node, std::vector<uint32_t> idx, const BBox3f& box, int depth) {
        int64_t n = 0;
        for (uint32_t i : idx) n += counts(i);
        if (n <= settings->max_samples || depth >= settings->max_depth) return make_leaf(node, idx);
        auto [axis, split] = choose_split(idx, box);
        if (axis == 3) return make_leaf(node, idx);
        std::vector<uint32_t> lower, upper;
        for (uint32_t i : idx) (points[i][axis] < split ? lower : upper).push_back(i);
        const bool parallel = idx.size() >= settings->parallel_min_samples;
        idx = {};
        const uint32_t child = uint32_t(nodes.size());
        nodes[node] = SpatialTree::Node{split, child, uint8_t(axis)};
        nodes.resize(nodes.size() + 2);
        BBox3f lo_box = box, hi_box = box;
        lo_box.hi[axis] = split;
        hi_box.lo[axis] = split;
        if (!parallel) {
            build(child, std::move(lower), lo_box, depth + 1);
            build(child + 1, std::move(upper), hi_box, depth + 1);
            return;
        }
        Builder halves[2] = {Builder(points, counted, *settings), Builder(points, counted, *settings)};
        std::vector<uint32_t>* parts[2] = {&lower, &upper};
        const BBox3f* boxes[2] = {&lo_box, &hi_box};
        parallel_for(0, 2, [&](int h) { halves[h].build(0, std::move(*parts[h]), *boxes[h], depth + 1); });
        splice(child, halves[0]);
        splice(child + 1, halves[1]);
    }

    // Appends a subtree built by `sub` (its root at sub.nodes[0]) as the sequential build would have
    // built it from `node`: its other nodes after the current ones, its leaves after the current ones.
    void splice(uint32_t node, const Builder& sub) {
        const uint32_t base = uint32_t(nodes.size()) - 1;  // sub's node i >= 1 goes to base + i
        const uint32_t first_leaf = uint32_t(leaf_offset.size()) - 1;
        const uint32_t first_sample = uint32_t(order.size());
        auto moved = [&](SpatialTree::Node n) {
            n.child += n.is_leaf() ? first_leaf : base;
            return n;
        };
        nodes[node] = moved(sub.nodes[0]);
        nodes.reserve(nodes.size() + sub.nodes.size() - 1);
        for (size_t i = 1; i < sub.nodes.size(); ++i) nodes.push_back(moved(sub.nodes[i]));
        order.insert(order.end(), sub.order.begin(), sub.order.end());
        for (size_t l = 1; l < sub.leaf_offset.size(); ++l) leaf_offset.push_back(first_sample + sub.leaf_offset[l]);
    }
};

}  // namespace

SpatialTree SpatialTree::build(const BBox3f& bounds, std::span<const Point3f> points,
                               const SpatialTreeSettings& settings, std::span<const uint8_t> counted) {
    if (!counted.empty() && counted.size() != points.size())
        throw std::invalid_argument("SpatialTree::build: one `counted` flag per point expected");
    if (!bounds.valid()) throw std::invalid_argument("SpatialTree::build: invalid bounds");
    if (settings.max_samples < 1 || settings.max_depth < 0 || settings.max_depth > 60)
        throw std::invalid_argument("SpatialTree::build: max_samples must be >= 1 and max_depth in [0, 60]");
    std::vector<Point3f> clamped(points.begin(), points.end());
    for (Point3f& p : clamped) p = min(max(p, bounds.lo), bounds.hi);

    SpatialTree tree(bounds);
    std::vector<uint32_t> all(points.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = uint32_t(i);
    Builder b(clamped, counted, settings);
    b.order.reserve(points.size());
    b.build(0, std::move(all), bounds, 0);
    tree.nodes_ = std::move(b.nodes);
    tree.sample_index_ = std::move(b.order);
    tree.leaf_offset_ = std::move(b.leaf_offset);
    tree.compute_leaf_bounds();
    return tree;
}

SpatialTree::RayCursor::RayCursor(const SpatialTree& tree, const Ray& ray, float t0, float t1, int start)
    : tree_(&tree) {
    for (int a = 0; a < 3; ++a) {
        o_[a] = ray.o[a];
        d_[a] = ray.d[a];
        inv_d_[a] = 1.f / ray.d[a];
        moving_[a] = d_[a] != 0.f;
        up_[a] = d_[a] >= 0.f;
        exit_face_[a] = d_[a] > 0.f ? 1 : 0;
    }
    finite_ = std::isfinite(inv_d_[0]) && std::isfinite(inv_d_[1]) && std::isfinite(inv_d_[2]);
    float b0, b1;
    if (!tree.bounds_.ray_intersect(ray, b0, b1)) return;
    t_ = std::max(t0, b0);
    t_end_ = std::min(t1, b1);
    if (!(t_ < t_end_)) return;
    const float p[3] = {o_[0] + d_[0] * t_, o_[1] + d_[1] * t_, o_[2] + d_[2] * t_};
    if (start >= 0 && start < tree.leaf_count()) {
        // Strictly inside: no split plane through p, so the descent (whose ties follow the ray) would
        // end in this leaf too.
        const BBox3f& b = tree.leaves_[size_t(start)].box;
        if (p[0] > b.lo.x && p[0] < b.hi.x && p[1] > b.lo.y && p[1] < b.hi.y && p[2] > b.lo.z && p[2] < b.hi.z) {
            leaf_ = start;
            return;
        }
    }
    leaf_ = int(tree.nodes_[descend(0u, p)].child);
}

void SpatialTree::build_jump_grid() {
    jump_ = Jump{};
    const Vec3f e = bounds_.extents();
    const double volume = double(e.x) * double(e.y) * double(e.z);
    if (!(volume > 0.0) || !std::isfinite(volume)) return;
    const double cell = std::cbrt(volume / (2.0 * double(std::max<size_t>(leaves_.size(), 1))));
    const double lo[3] = {bounds_.lo.x, bounds_.lo.y, bounds_.lo.z}, ext[3] = {e.x, e.y, e.z};
    double size[3], margin = 0.0;
    for (int a = 0; a < 3; ++a) {
        jump_.n[a] = int(std::clamp(std::ceil(ext[a] / cell), 1.0, 256.0));
        jump_.scale[a] = float(double(jump_.n[a]) / ext[a]);
        size[a] = ext[a] / double(jump_.n[a]);
        margin = std::max({margin, 1e-3 * size[a], 1e-6 * std::abs(lo[a]), 1e-6 * std::abs(lo[a] + ext[a])});
    }
    jump_.node.assign(size_t(jump_.n[0]) * size_t(jump_.n[1]) * size_t(jump_.n[2]), 0u);
    for (int z = 0; z < jump_.n[2]; ++z)
        for (int y = 0; y < jump_.n[1]; ++y)
            for (int x = 0; x < jump_.n[0]; ++x) {
                const int i[3] = {x, y, z};
                // The deepest node whose every split on the way puts the whole cell (with the margin) on
                // one side: p goes up iff p >= split.
                uint32_t node = 0;
                while (!nodes_[node].is_leaf()) {
                    const Node& n = nodes_[node];
                    const double c0 = lo[n.axis] + size[n.axis] * i[n.axis] - margin;
                    const double c1 = lo[n.axis] + size[n.axis] * (i[n.axis] + 1) + margin;
                    if (c1 < double(n.split))
                        node = n.child;
                    else if (c0 >= double(n.split))
                        node = n.child + 1;
                    else
                        break;
                }
                jump_.node[(size_t(z) * size_t(jump_.n[1]) + size_t(y)) * size_t(jump_.n[0]) + size_t(x)] = node;
            }
}

void SpatialTree::compute_leaf_bounds() {
    size_t leaves = 0;
    for (const Node& n : nodes_) leaves += n.is_leaf();
    leaves_.assign(leaves, LeafRecord{BBox3f(), {kNoRope, kNoRope, kNoRope, kNoRope, kNoRope, kNoRope}});
    int depth = 0;
    struct Item {
        uint32_t node;
        BBox3f box;
        int depth;
    };
    std::vector<Item> stack{{0u, bounds_, 0}};
    while (!stack.empty()) {
        Item it = stack.back();
        stack.pop_back();
        depth = std::max(depth, it.depth);
        const Node& n = nodes_[it.node];
        if (n.is_leaf()) {
            leaves_[n.child].box = it.box;
            continue;
        }
        BBox3f lo = it.box, hi = it.box;
        lo.hi[n.axis] = n.split;
        hi.lo[n.axis] = n.split;
        stack.push_back({n.child, lo, it.depth + 1});
        stack.push_back({n.child + 1, hi, it.depth + 1});
    }
    depth_ = depth;
    build_jump_grid();

    // Ropes: from the root towards the region just beyond each leaf face, as long as the face's
    // rectangle lies on one side of the splits met; stop at the first node that cuts it.
    for (size_t leaf = 0; leaf < leaves; ++leaf) {
        const BBox3f& box = leaves_[leaf].box;
        for (int face = 0; face < 6; ++face) {
            const int a = face / 2;
            const bool up = face % 2 == 1;
            const float plane = up ? box.hi[a] : box.lo[a];
            if (plane == (up ? bounds_.hi[a] : bounds_.lo[a])) continue;  // on the bounds
            uint32_t node = 0;
            while (!nodes_[node].is_leaf()) {
                const Node& n = nodes_[node];
                int side;  // 0 lower, 1 upper, -1 the split cuts the face
                if (n.axis == a)
                    side = up ? (plane >= n.split ? 1 : 0) : (plane > n.split ? 1 : 0);
                else
                    side = box.hi[n.axis] <= n.split ? 0 : (box.lo[n.axis] >= n.split ? 1 : -1);
                if (side < 0) break;
                node = n.child + uint32_t(side);
            }
            leaves_[leaf].rope[face] = node;
        }
    }
}

SpatialTree SpatialTree::from_nodes(const BBox3f& bounds, std::vector<Node> nodes) {
    if (!bounds.valid()) throw std::invalid_argument("spatial tree: invalid bounds");
    if (nodes.empty()) throw std::invalid_argument("spatial tree: no nodes");
    // Every node reachable exactly once from the root, children after their parent, leaves
    // numbered 0..L-1 each once, depth within the traversal stack, splits inside their boxes.
    std::vector<uint8_t> seen(nodes.size(), 0);
    std::vector<uint8_t> leaf_seen;
    size_t leaves = 0;
    for (const Node& n : nodes) leaves += n.is_leaf();
    leaf_seen.assign(leaves, 0);
    struct Item {
        uint32_t node;
        BBox3f box;
        int depth;
    };
    std::vector<Item> stack{{0u, bounds, 0}};
    size_t visited = 0;
    while (!stack.empty()) {
        Item it = stack.back();
        stack.pop_back();
        if (it.node >= nodes.size() || seen[it.node]) throw std::invalid_argument("spatial tree: malformed node links");
        seen[it.node] = 1;
        ++visited;
        const Node& n = nodes[it.node];
        if (n.axis > 3) throw std::invalid_argument("spatial tree: invalid split axis");
        if (n.is_leaf()) {
            if (n.child >= leaves || leaf_seen[n.child]) throw std::invalid_argument("spatial tree: invalid leaf index");
            leaf_seen[n.child] = 1;
            continue;
        }
        if (it.depth >= 60) throw std::invalid_argument("spatial tree: too deep");
        if (n.child <= it.node || size_t(n.child) + 1 >= nodes.size())
            throw std::invalid_argument("spatial tree: malformed node links");
        if (!(n.split > it.box.lo[n.axis] && n.split < it.box.hi[n.axis]))
            throw std::invalid_argument("spatial tree: split outside its node");
        BBox3f lo = it.box, hi = it.box;
        lo.hi[n.axis] = n.split;
        hi.lo[n.axis] = n.split;
        stack.push_back({n.child, lo, it.depth + 1});
        stack.push_back({n.child + 1, hi, it.depth + 1});
    }
    if (visited != nodes.size()) throw std::invalid_argument("spatial tree: unreachable nodes");
    SpatialTree tree(bounds);
    tree.nodes_ = std::move(nodes);
    tree.leaf_offset_.clear();
    tree.compute_leaf_bounds();
    return tree;
}

}  // namespace volguide
