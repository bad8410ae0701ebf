#pragma once
// The guiding field (docs/theory.md §5): a kd-tree over the media's bounds with, per leaf, a normalised
// VMM of incident radiance V_L (directions towards the light, §1.1) and the RGB fluence Phi, so that
//   incident radiance      L~(x, w)   = Phi * V_L(w)
//   in-scattered radiance  L~_i(x, w) = Phi * (V_L convolved with the phase VMM)(w), w = travel direction.
// The field only shapes probabilities; weights never read it (docs/theory.md §1.4).
//
// It is built from radiance samples the renderer produces (photon collisions or camera-path
// vertices); it never sees the scene. Leaves are fitted in parallel, each from its own samples in
// input order, so the field is a pure function of the samples for any thread count.
#include <span>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/guiding/spatial_tree.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/vmm_fit.h"

namespace volguide {

// One training record: at `position`, radiance arrives from `direction` (towards the light).
// `weight` is its fluence contribution: Phi_p / sigma_t for a photon collision (collision
// estimator, docs/theory.md §2.5, §5.2), or L^ / p(direction) for a camera-path vertex (§10.2).
// `count` is the sample's share of the PerSampleMean divisor: 1 per camera-path vertex; 0 for a
// vertex's NEE sample, a second MIS strategy's sample of the same vertex (a library user's camera-path
// training; volguide's renderer trains from photons).
struct RadianceSample {
    Point3f position;
    Vec3f direction;
    Color3 weight;
    float count = 1.f;
    // Light that came straight from an emitter (a photon's first collision): what next-event
    // estimation samples at every medium vertex. Fields whose samples carry this flag also fit
    // each leaf's distribution without it (GuidingLeaf::vmm_indirect).
    bool direct = false;
};

// How a leaf turns its samples' weights into fluence.
enum class FluenceEstimator {
    PerVolume,      // photons: Phi = sum(weight) / leaf volume
    PerSampleMean,  // camera vertices: Phi = sum(weight) / sum(count) (the number of vertices)
};

enum class InscatterMode {
    Exact,  // sum over lobe pairs of the exact vMF convolution value (docs/theory.md eq. 3.4)
    A3,     // the paper's single-lobe approximation A3(k') = A3(k1) A3(k2) (eq. 3.5 / 5.1)
};

struct GuidingFieldSettings {
    SpatialTreeSettings tree;  // tree.max_samples is `leaf_samples`
    int lobes = 8;             // VMM components per leaf (docs/theory.md §15)
    int min_samples = 64;      // fewer (positive-weight) samples: the leaf is invalid
    VmmFitSettings fit;        // fit.initial_lobes is overridden by `lobes`
    FluenceEstimator fluence = FluenceEstimator::PerVolume;
};

struct GuidingLeaf {
    Vmm vmm;              // normalised; empty for an invalid leaf
    Color3 fluence{0.f};  // Phi (RGB)
    uint32_t samples = 0;
    bool valid = false;  // enough samples: guided decisions may use it (otherwise defensive only)
    // The directional shape of the light that did not come straight from an emitter (samples
    // without RadianceSample::direct), for direction guiding next to NEE. A field trained without
    // direct flags (from camera vertices) holds a copy of vmm / valid here.
    Vmm vmm_indirect;
    bool valid_indirect = false;
    // The share of the leaf's volume inside a scattering medium, measured by the renderer (it needs
    // the scene; GuidingField::set_medium_fractions); < 0: not measured.
    float medium_fraction = -1.f;
    // The leaf is mostly medium: its samples describe the light in the space around any point of
    // it, so it may guide the surfaces inside it (a floor beside a dense sphere shares a large leaf
    // with the sphere's inside, whose radiance it does not see). False when not measured.
    bool mostly_medium() const { return medium_fraction >= kMostlyMediumFraction; }
    static constexpr float kMostlyMediumFraction = 0.5f;
};

class GuidingField {
  public:
    GuidingField() = default;
    static GuidingField build(const BBox3f& bounds, std::span<const RadianceSample> samples,
                              const GuidingFieldSettings& settings = {});
    // Assembles a field from its parts (loading); leaves.size() must equal tree.leaf_count().
    GuidingField(SpatialTree tree, std::vector<GuidingLeaf> leaves);

    const SpatialTree& tree() const { return tree_; }
    const std::vector<GuidingLeaf>& leaves() const { return leaves_; }
    bool empty() const { return leaves_.empty(); }

    // Stores each leaf's medium fraction (fractions[leaf] in [0, 1], measured by the renderer:
    // integrators/guided/training/medium_occupancy.h). With scale_fluence (per-volume photon fields, once): per-volume
    // fluence averages the collision estimator over the whole leaf, but collisions only happen
    // where there is a medium, so a leaf half outside a fog sphere would read half the fluence;
    // each leaf's fluence is divided by its fraction (a fraction of 0 leaves the leaf unchanged).
    void set_medium_fractions(std::span<const float> fractions, bool scale_fluence);
    // Whether the leaves' medium fractions were measured (set_medium_fractions, or loaded).
    bool has_medium_fractions() const { return !leaves_.empty() && leaves_.front().medium_fraction >= 0.f; }

    // The leaf at x, or nullptr outside the field's bounds.
    const GuidingLeaf* leaf_at(const Point3f& x) const {
        const int l = leaves_.empty() ? -1 : tree_.leaf_at(x);
        return l < 0 ? nullptr : &leaves_[size_t(l)];
    }

    // L~(x, w), w towards the light; 0 outside the field or in invalid leaves.
    Color3 incident(const Point3f& x, const Vec3f& w) const;
    // L~_i(x, w) for a ray travelling along w through a medium whose phase VMM is `phase`.
    Color3 inscattered(const Point3f& x, const Vec3f& w, const PhaseVmm& phase,
                       InscatterMode mode = InscatterMode::Exact) const;

    static Color3 incident(const GuidingLeaf& leaf, const Vec3f& w);
    static Color3 inscattered(const GuidingLeaf& leaf, const Vec3f& w, const PhaseVmm& phase,
                              InscatterMode mode);

  private:
    SpatialTree tree_;
    std::vector<GuidingLeaf> leaves_;
};

}  // namespace volguide
