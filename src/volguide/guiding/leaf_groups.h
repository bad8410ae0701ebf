#pragma once
// The groups the guided distance walk steps through (issue 20): the field's kd-tree with every
// subtree whose leaves' distance estimates agree merged into one group.
//
// A distance decision that crosses a ray through the fog steps every leaf it crosses (a lookup, an
// exponential and a rope step each: a large share of a guided sample, bench/RESULTS.md (issue 35)),
// although neighbouring leaves often hold nearly the same L~_i and L~ for every direction — the
// kd-tree splits by sample count, not by how the radiance changes. Here sibling subtrees are merged
// bottom-up while the spread of their leaves' scalar estimates (max - min over the leaves, relative
// to the max), averaged over the texels of their octahedral tables (leaf_estimates.h), is at most a
// `tolerance` for L~_i and for L~ alike. A mean, not a maximum: neighbouring leaves' fitted lobes
// disagree strongly in a few directions (fit noise) while most of the sphere agrees, and a
// per-texel rule merged almost nothing on the benchmark fields. The merged group's tables are the
// volume-weighted average of its leaves'. The walk then steps groups (fewer bins: fewer lookups,
// exponentials and rope steps).
//
// Like the tables, the groups only shape the distance sampler's probabilities (its pdf is computed
// from the same bins it sampled with; weights use the true coefficients): unbiased for any
// tolerance. Tolerance 0 merges only leaves with identical tables (and invalid ones).
//
// A group's confidence length (WalkGuide's leaf_tau_max rule) is the largest extent of its leaves:
// merging says the estimates do not vary across the group at the leaves' resolution, not that a
// leaf many mean free paths across has become more trustworthy.
#include <cstdint>
#include <vector>

#include "volguide/core/vec.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/spatial_tree.h"

namespace volguide {

class LeafGroups {
  public:
    // `fine`: the field's tree; `estimates`: its leaves' tables (resolution > 0); `leaf_extent`:
    // per leaf, the cube root of its volume. `fine` must outlive this object.
    LeafGroups(const SpatialTree& fine, const LeafEstimates& estimates, const std::vector<float>& leaf_extent,
                    float tolerance);

    // The groups as a kd-tree of their own (its leaves are the groups): RayCursor walks it.
    const SpatialTree& tree() const { return tree_; }
    int group_count() const { return tree_.leaf_count(); }

    // Channel-average L~_i(w) and L~(w) of a group (what a bin reads); false for an invalid one.
    // `d` from the estimates' prepare(): the groups' tables share the leaves' layout.
    bool lookup(int group, const LeafEstimates::Direction& d, float& inscattered, float& incident) const {
        const Header& h = headers_[size_t(group)];
        if (!h.valid) return false;
        float inscattered_texel, incident_texel;
        d.interpolate(&texels_[size_t(group) * texels_per_table_], inscattered_texel, incident_texel);
        inscattered = h.scale_inscattered * inscattered_texel;
        incident = h.scale_incident * incident_texel;
        return true;
    }
    void prefetch(int group, const LeafEstimates::Direction& d) const {
        if (group < 0) return;
        __builtin_prefetch(&headers_[size_t(group)]);
        d.prefetch(&texels_[size_t(group) * texels_per_table_]);
    }
    // The largest extent of the group's leaves (the confidence length).
    float extent(int group) const { return headers_[size_t(group)].extent; }
    // The field's leaf holding p, p in `group` (a descent from the group's root in the field's tree).
    int fine_leaf(int group, const Point3f& p) const {
        return fine_->leaf_below(headers_[size_t(group)].fine_node, p);
    }

  private:
    struct Header {
        float scale_inscattered = 0.f, scale_incident = 0.f;  // value = scale * texel
        float extent = 0.f;
        uint32_t fine_node = 0;
        bool valid = false;
    };
    const SpatialTree* fine_;
    SpatialTree tree_;
    size_t texels_per_table_ = 0;
    std::vector<Header> headers_;
    std::vector<EstimateTexel> texels_;
};

}  // namespace volguide
