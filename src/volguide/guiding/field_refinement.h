#pragma once
// A photon field that keeps learning while the image renders (docs/theory.md §22, issue 39).
//
// The pre-pass builds the field once (GuidingField::build); FieldRefinement then keeps, per leaf, the
// sufficient statistics of everything it has seen instead of the samples: the photons' flux, the count
// of samples, the first moment of their directions and the VMM's EM statistics. Each later photon pass
// is added to them without revisiting the earlier ones, so the memory is the leaves', not the photons':
//   - every leaf's VMMs take one incremental EM step on the pass's samples of the leaf (statistics
//     summed over passes, docs/theory.md §22.2), then split lobes its samples show to be two and merge
//     lobes that became one (vmm_split_merge.h); the statistics follow the new lobes;
//   - a leaf whose samples exceed leaf_samples x (photons seen / first pass's photons)^split_growth
//     splits where its new samples lie (as the kd-tree's build splits), the children inheriting
//     its statistics in proportion: the tree refines with the budget, where the light is;
//   - two sibling leaves whose fluence density and mean direction agree within the merge thresholds
//     merge back into their parent: the tree stays coarse where the light is smooth;
//   - the leaves never exceed max_leaves (the split threshold rises instead).
// Leaves are updated in parallel, each from its own samples in input order, and the tree is changed in
// leaf order: the field is a pure function of the passes for any thread count.
#include <cstddef>
#include <span>
#include <vector>

#include "volguide/guiding/guiding_field.h"

namespace volguide {

struct FieldRefinementSettings {
    GuidingFieldSettings field;  // leaf_samples, lobes, min_samples, the EM's settings (per-volume fluence)
    int max_leaves = 1 << 16;
    // The split threshold grows as the photons' count to this power (Müller et al.'s sqrt(2^k) rule):
    // leaves get finer and their samples more numerous as the budget grows.
    double split_growth = 0.5;
    // Siblings merge when |d_a - d_b| / (d_a + d_b) of their fluence densities is below merge_contrast
    // and their mean directions (first moments) differ by less than merge_direction. 0: never merge.
    float merge_contrast = 0.1f;
    float merge_direction = 0.1f;
    int em_iterations = 8;       // incremental EM steps per pass (fewer when the likelihood converges)
    bool lobe_split_merge = true;  // adapt each leaf's lobe count to its samples (at most field.lobes)
    int lobe_split_samples = 512;  // the lobe split test reads at most this many of a pass's samples per leaf
};

struct RefinementReport {
    int leaf_splits = 0, leaf_merges = 0;
    int lobe_splits = 0, lobe_merges = 0;
    int leaves = 0;
    double split_threshold = 0;  // samples per leaf past which a leaf split in this pass
};

class FieldRefinement {
  public:
    // Starts from `initial`, the field GuidingField::build made from `samples` (a photon pass of
    // `photons` photons, weights divided by them as trace_photons leaves them): its tree and leaves as
    // they are, their statistics from the samples.
    FieldRefinement(const GuidingField& initial, std::span<const RadianceSample> samples, double photons,
                    const FieldRefinementSettings& settings);
    // Adds a further photon pass (weights divided by its `photons`, as trace_photons leaves them).
    RefinementReport add(std::span<const RadianceSample> samples, double photons);
    // The field now (medium fractions not measured: the renderer measures them for the new leaves).
    GuidingField field() const;
    int leaf_count() const { return tree_.leaf_count(); }
    double photons() const { return photons_; }
    // The refinement's own memory: its leaves' statistics and mixtures, and the tree.
    size_t memory_bytes() const;

  private:
    // A leaf's directional distribution and the EM statistics it was fitted from (summed over passes).
    struct Shape {
        Vmm vmm;
        VmmStatistics stats;
        double seen = 0;  // samples behind stats
        bool valid = false;
    };
    struct LeafState {
        double flux[3] = {0, 0, 0};  // sum over passes of photons x the samples' weights
        double samples = 0;          // positive-weight samples since the leaf was made (split decisions)
        Vec3d moment{0.0};           // sum of weight x direction (merge decisions)
        double moment_weight = 0;
        float split_scale = 1.f;  // a merged leaf waits for this many times the threshold before splitting
        bool any_direct = false;
        Shape all, indirect;
    };
    struct Grown;  // a leaf's subtree after a pass (field_refinement.cpp)

    static VmmFitSettings fit_settings(const FieldRefinementSettings& settings);
    // The pass's samples of a leaf into its statistics and one incremental fit of its mixtures.
    void update(LeafState& state, std::span<const uint32_t> idx, std::span<const RadianceSample> samples,
                double photons, RefinementReport& report) const;
    static void update_with(const FieldRefinementSettings& settings, LeafState& state, std::span<const uint32_t> idx,
                            std::span<const RadianceSample> samples, double photons, RefinementReport& report);
    static void update_shape(const FieldRefinementSettings& settings, Shape& shape,
                             std::span<const DirectionalSample> dirs, RefinementReport& report);
    static LeafState part(const LeafState& state, double count, double flux);
    static LeafState merge(const LeafState& a, const LeafState& b);
    void grow_into(Grown& g, uint32_t node, LeafState state, std::vector<uint32_t> idx, const BBox3f& box, int extra,
                   std::span<const RadianceSample> samples, double photons, double threshold) const;
    double split_threshold(std::span<const double> expected_samples) const;
    bool similar(const LeafState& a, const BBox3f& box_a, const LeafState& b, const BBox3f& box_b) const;
    void merge_smooth_siblings(RefinementReport& report);
    void rebuild(std::vector<SpatialTree::Node> nodes, std::vector<LeafState> states);

    FieldRefinementSettings settings_;
    SpatialTree tree_;
    std::vector<LeafState> leaves_;  // by the tree's leaf index
    double photons_ = 0, first_photons_ = 0;
};

}  // namespace volguide
