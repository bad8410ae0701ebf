#pragma once
// The prepared field: what every guided decision of `guided_volpath`'s walk reads of the guiding field
// (docs/theory.md §7–9), prepared from it once — per phase function, the in-scattered cache, the
// per-leaf tables of L~_i and L~ (leaf_estimates.h), the leaf groups of the distance walk
// (leaf_groups.h) and the phase function's lobes; per leaf, its extent (its confidence length,
// trust.h) and the direction decisions' lobe block (the indirect light). Read-only after
// construction, shared by every walk. A decision for one phase function reads it through a
// PhaseField (the distance decision's context, distance_sampler.h).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/media/phase.h"
#include "volguide/vmm/lobe_block.h"
#include "volguide/vmm/lobe_product.h"

namespace volguide {

class Scene;

// The prepared field as the decisions for one phase function read it: the field and each leaf's
// extent, and what was prepared for the phase (null where nothing was: a phase function of no medium
// of the scene, or tables and groups no decision asked for).
struct PhaseField {
    const GuidingField* field = nullptr;
    const std::vector<float>* leaf_extent = nullptr;
    const InscatterCache* inscatter = nullptr;
    const LeafEstimates* estimates = nullptr;  // the per-leaf tables (guided distance decisions only)
    const LeafGroups* groups = nullptr;        // the distance walk's leaf groups (distance_merge > 0)
    const PhaseLobes* lobes = nullptr;

    // The field's estimates at the valid leaf `leaf`: L~_i(x, d) for a ray along d, and L~(x, w)
    // arriving from w, from the per-leaf tables when they exist.
    Color3 inscattered(int leaf, const Vec3f& d) const;
    Color3 incident(int leaf, const Vec3f& w) const;
    // The guided volume scattering probability of a segment leaving the valid leaf `leaf` along w
    // (docs/theory.md §7.10): P_G = albedo (1 - T) <L~_i(w)> / <L~(w)>, clamped to [0, 1], with
    // `unguided` = 1 - T the segment's unguided scattering probability, from the leaf's tables
    // (one lookup). NaN (the caller takes the unguided probability) for leaf < 0 or where the
    // estimates say nothing (L~ and L~_i both 0, or not finite). It shapes a probability only.
    float scatter_probability(int leaf, const Vec3f& w, float albedo, float unguided) const;
};

// What is prepared: the distance decisions' tables (their resolution per side; 0: exact VMM evaluation
// per leaf crossed) and groups (the merge tolerance; 0: none).
struct PreparedFieldSettings {
    bool distance_tables = false;  // a guided distance decision reads them
    int estimate_table = 16;
    float distance_merge = 0.f;
};

class PreparedField {
  public:
    // For every phase function of the scene's media. The field must outlive the object.
    PreparedField(const Scene& scene, const GuidingField& field, const PreparedFieldSettings& settings);

    const GuidingField& field() const { return field_; }
    // What the decisions for `phase` read (one map lookup by its mean cosine: callers keep it per medium).
    PhaseField phase(const PhaseFunction& phase) const;

    // The leaf at x (-1 outside the field), without a descent when `hint` (a guess: a nearby
    // vertex's leaf) holds x; `descents` counts the descent made.
    int leaf_at(const Point3f& x, int hint, uint64_t& descents) const;
    const std::vector<float>& leaf_extents() const { return leaf_extent_; }

    // The estimates prepared for a phase function (null: none, e.g. no guided distance decision).
    const LeafEstimates* estimates_for(const PhaseFunction& phase) const { return this->phase(phase).estimates; }
    const LeafGroups* groups_for(const PhaseFunction& phase) const { return this->phase(phase).groups; }
    // The phase function's lobes, prepared once per phase mean cosine (null: a phase function of no
    // medium of the scene).
    const PhaseLobes* phase_lobes(const PhaseFunction& phase) const { return this->phase(phase).lobes; }
    // The distribution the direction decisions follow in `leaf` (a valid index), as a lobe block
    // (empty where the leaf has none): the leaf's indirect light (GuidingLeaf::vmm_indirect): NEE
    // already samples the light that comes straight from the emitters at every vertex, so the
    // continuation's zero-variance target is f_p times the rest (docs/theory.md §8.3). One copy of
    // every leaf's mixture at its own lobe count, shared by every decision.
    LobeBlock direction_lobes(int leaf) const { return direction_lobes_.block(leaf); }
    // Hints the cache that `leaf`'s block will be read soon (a vertex that found its leaf).
    void prefetch_direction_lobes(int leaf) const { direction_lobes_.prefetch(leaf); }
    // The same mixture as the field holds it (the surface guide's product reads it), null where the
    // leaf has none.
    const Vmm* direction_vmm(int leaf) const;

    // PhaseField's estimates for `phase` (guided RR and splitting, docs/theory.md §9.3).
    Color3 inscattered(int leaf, const PhaseFunction& phase, const Vec3f& d) const {
        return this->phase(phase).inscattered(leaf, d);
    }
    Color3 incident(int leaf, const PhaseFunction& phase, const Vec3f& w) const {
        return this->phase(phase).incident(leaf, w);
    }
    float scatter_probability(int leaf, const PhaseFunction& phase, const Vec3f& w, float albedo,
                              float unguided) const {
        return this->phase(phase).scatter_probability(leaf, w, albedo, unguided);
    }

    // Memory per leaf of what the decisions read (--stats): the direction decisions' lobe blocks, the
    // estimate tables (every phase function's), the kd-tree (nodes and leaf records) and the field's
    // own leaf (its mixtures at full capacity, which training fills and no decision reads).
    std::vector<std::pair<std::string, double>> memory_named() const;
    // The distance walk's leaf groups per phase mean cosine and their total (0 without merging).
    size_t leaf_group_count() const;

  private:
    // What is prepared for one phase function.
    struct Prepared {
        InscatterCache inscatter;
        PhaseLobes lobes;
        std::optional<LeafEstimates> estimates;  // reads inscatter
        std::optional<LeafGroups> groups;        // built on estimates, if merging
    };
    const GuidingField& field_;
    std::map<float, Prepared> phases_;  // by phase mean cosine (node addresses stay: estimates read inscatter)
    std::vector<float> leaf_extent_;    // cube root of each leaf's volume
    LobeStore direction_lobes_;                  // per leaf: vmm_indirect where valid_indirect
};

}  // namespace volguide
