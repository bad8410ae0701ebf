#include "volguide/guiding/leaf_groups.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <unordered_map>

namespace volguide {

namespace {

// The scalar tables of a candidate group and, per texel, the range its leaves span.
struct Candidate {
    bool valid = false;
    double volume = 0.0;
    float extent = 0.f;
    std::vector<float> inscattered, L;                      // volume-weighted averages
    std::vector<float> inscattered_lo, inscattered_hi, L_lo, L_hi;  // per texel, over the leaves
};

float max_of(const std::vector<float>& v) {
    return v.empty() ? 0.f : *std::max_element(v.begin(), v.end());
}

// Whether a and b may form one group: over the texels, the mean spread of their leaves' values
// (max - min, relative to max plus a floor of 1e-3 of the largest value) is at most `tolerance`,
// for L~_i and for L~ alike. A mean, not a maximum: neighbouring leaves' fitted lobes differ a lot
// in a few directions (a sibling pair's largest per-texel difference of L~ is ~0.6-0.8 on the
// benchmark fields) while most of the sphere agrees.
bool agree(const Candidate& a, const Candidate& b, float tolerance) {
    if (a.valid != b.valid) return false;
    if (!a.valid) return true;
    const float floor_i = 1e-3f * std::max(max_of(a.inscattered_hi), max_of(b.inscattered_hi));
    const float floor_l = 1e-3f * std::max(max_of(a.L_hi), max_of(b.L_hi));
    double spread_i = 0.0, spread_l = 0.0;
    for (size_t k = 0; k < a.inscattered.size(); ++k) {
        const float li_lo = std::min(a.inscattered_lo[k], b.inscattered_lo[k]), li_hi = std::max(a.inscattered_hi[k], b.inscattered_hi[k]);
        const float l_lo = std::min(a.L_lo[k], b.L_lo[k]), l_hi = std::max(a.L_hi[k], b.L_hi[k]);
        spread_i += (li_hi - li_lo) / (li_hi + floor_i);
        spread_l += (l_hi - l_lo) / (l_hi + floor_l);
    }
    const double n = double(a.inscattered.size());
    return spread_i <= tolerance * n && spread_l <= tolerance * n;
}

Candidate merge(const Candidate& a, const Candidate& b) {
    Candidate m = a;
    m.volume = a.volume + b.volume;
    m.extent = std::max(a.extent, b.extent);
    if (!m.valid) return m;
    const double wa = m.volume > 0.0 ? a.volume / m.volume : 0.5, wb = 1.0 - wa;
    for (size_t k = 0; k < m.inscattered.size(); ++k) {
        m.inscattered[k] = float(wa * a.inscattered[k] + wb * b.inscattered[k]);
        m.L[k] = float(wa * a.L[k] + wb * b.L[k]);
        m.inscattered_lo[k] = std::min(a.inscattered_lo[k], b.inscattered_lo[k]);
        m.inscattered_hi[k] = std::max(a.inscattered_hi[k], b.inscattered_hi[k]);
        m.L_lo[k] = std::min(a.L_lo[k], b.L_lo[k]);
        m.L_hi[k] = std::max(a.L_hi[k], b.L_hi[k]);
    }
    return m;
}

}  // namespace

LeafGroups::LeafGroups(const SpatialTree& fine, const LeafEstimates& estimates,
                                 const std::vector<float>& leaf_extent, float tolerance)
    : fine_(&fine) {
    const int R = estimates.resolution();
    if (R <= 0) throw std::invalid_argument("leaf groups need the leaves' estimate tables");
    if (leaf_extent.size() != size_t(fine.leaf_count()))
        throw std::invalid_argument("leaf groups: one extent per leaf expected");
    texels_per_table_ = size_t(R * R);
    const std::vector<SpatialTree::Node>& nodes = fine.nodes();

    // Bottom-up: a subtree stays a candidate while its two halves agree; where they do not, each
    // half that is still a candidate becomes a group.
    std::unordered_map<uint32_t, Candidate> groups;  // by the fine node at the group's root
    auto leaf_candidate = [&](int leaf) {
        Candidate c;
        c.inscattered.assign(texels_per_table_, 0.f);
        c.L.assign(texels_per_table_, 0.f);
        c.valid = estimates.texel_averages(leaf, c.inscattered.data(), c.L.data());
        const Vec3f e = fine.leaf_bounds(leaf).extents();
        c.volume = double(e.x) * double(e.y) * double(e.z);
        c.extent = leaf_extent[size_t(leaf)];
        c.inscattered_lo = c.inscattered_hi = c.inscattered;
        c.L_lo = c.L_hi = c.L;
        return c;
    };
    auto visit = [&](auto&& self, uint32_t node) -> std::optional<Candidate> {
        const SpatialTree::Node& n = nodes[node];
        if (n.is_leaf()) return leaf_candidate(int(n.child));
        std::optional<Candidate> lo = self(self, n.child), hi = self(self, n.child + 1);
        if (lo && hi && agree(*lo, *hi, tolerance)) return merge(*lo, *hi);
        if (lo) groups.emplace(n.child, std::move(*lo));
        if (hi) groups.emplace(n.child + 1, std::move(*hi));
        return std::nullopt;
    };
    if (std::optional<Candidate> root = visit(visit, 0u)) groups.emplace(0u, std::move(*root));

    // The groups' tree: the field's nodes above the groups, a leaf at each group's root.
    std::vector<SpatialTree::Node> out(1);
    headers_.reserve(groups.size());
    texels_.reserve(groups.size() * texels_per_table_);
    auto emit = [&](auto&& self, uint32_t node, size_t at) -> void {
        const auto it = groups.find(node);
        if (it != groups.end()) {
            const Candidate& c = it->second;
            SpatialTree::Node leaf;
            leaf.axis = 3;
            leaf.child = uint32_t(headers_.size());
            out[at] = leaf;
            Header h;
            h.valid = c.valid;
            h.extent = c.extent;
            h.fine_node = node;
            const float max_i = max_of(c.inscattered), max_l = max_of(c.L);
            h.scale_inscattered = max_i / 65535.f;
            h.scale_incident = max_l / 65535.f;
            headers_.push_back(h);
            for (size_t k = 0; k < texels_per_table_; ++k)
                texels_.push_back(c.valid ? EstimateTexel{quantise_texel(c.inscattered[k], max_i), quantise_texel(c.L[k], max_l)}
                                     : EstimateTexel{0, 0});
            return;
        }
        const SpatialTree::Node& n = nodes[node];
        const size_t children = out.size();
        out.resize(children + 2);
        SpatialTree::Node inner;
        inner.split = n.split;
        inner.axis = n.axis;
        inner.child = uint32_t(children);
        out[at] = inner;
        self(self, n.child, children);
        self(self, n.child + 1, children + 1);
    };
    emit(emit, 0u, 0);
    tree_ = SpatialTree::from_nodes(fine.bounds(), std::move(out));
}

}  // namespace volguide
