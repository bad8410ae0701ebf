#pragma once
// The regions the guided distance walk steps through (issue 20): the field's kd-tree with every
// subtree whose leaves' distance estimates agree merged into one region.
//
// A distance decision that crosses a ray through the fog steps every leaf it crosses (a lookup, an
// exponential and a rope step each: a large share of a guided sample, bench/RESULTS.md (issue 35)),
// although neighbouring leaves often hold nearly the same L~_i and L~ for every direction — the
// kd-tree splits by sample count, not by how the radiance changes. Here sibling subtrees are merged
// bottom-up while the spread of their leaves' scalar estimates (max - min over the leaves, relative
// to the max), averaged over the texels of their octahedral tables (leaf_estimates.h), is at most a
// `tolerance` for L~_i and for L~ alike. A mean, not a maximum: neighbouring leaves' fitted lobes
// disagree strongly in a few directions (fit noise) while most of the sphere agrees, and a
// per-texel rule merged almost nothing on the benchmark fields. The merged region's tables are the
// volume-weighted average of its leaves'. The walk then steps regions (fewer bins: fewer lookups,
// exponentials and rope steps).
//
// Like the tables, the regions only shape the distance sampler's probabilities (its pdf is computed
// from the same bins it sampled with; weights use the true coefficients): unbiased for any
// tolerance. Tolerance 0 merges only leaves with identical tables (and invalid ones).
//
// A region's confidence length (WalkGuide's leaf_tau_max rule) is the largest extent of its leaves:
// merging says the estimates do not vary across the region at the leaves' resolution, not that a
// leaf many mean free paths across has become more trustworthy.
#include <cstdint>
#include <vector>

#include "volguide/core/vec.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/spatial_tree.h"

namespace volguide {

class DistanceRegions {
  public:
    // `fine`: the field's tree; `estimates`: its leaves' tables (resolution > 0); `leaf_extent`:
    // per leaf, the cube root of its volume. `fine` must outlive this object.
    DistanceRegions(const SpatialTree& fine, const LeafEstimates& estimates, const std::vector<float>& leaf_extent,
                    float tolerance);

    // The regions as a kd-tree of their own (its leaves are the regions): RayCursor walks it.
    const SpatialTree& tree() const { return tree_; }
    int region_count() const { return tree_.leaf_count(); }

    // Channel-average L~_i(w) and L~(w) of a region (what a bin reads); false for an invalid one.
    // `d` from the estimates' prepare(): the regions' tables share the leaves' layout.
    bool lookup(int region, const LeafEstimates::Direction& d, float& Li, float& L) const {
        const Header& h = headers_[size_t(region)];
        if (!h.valid) return false;
        float inscattered, incident;
        d.interpolate(&texels_[size_t(region) * texels_per_table_], inscattered, incident);
        Li = h.scale_inscattered * inscattered;
        L = h.scale_incident * incident;
        return true;
    }
    void prefetch(int region, const LeafEstimates::Direction& d) const {
        if (region < 0) return;
        __builtin_prefetch(&headers_[size_t(region)]);
        d.prefetch(&texels_[size_t(region) * texels_per_table_]);
    }
    // The largest extent of the region's leaves (the confidence length).
    float extent(int region) const { return headers_[size_t(region)].extent; }
    // The field's leaf holding p, p in `region` (a descent from the region's root in the field's tree).
    int fine_leaf(int region, const Point3f& p) const {
        return fine_->leaf_below(headers_[size_t(region)].fine_node, p);
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
