#pragma once
// The guided direction decision of a diffuse surface vertex (the surface counterpart of GuidedVertex):
// BSDF sampling mixed with the guide of the leaf beside the surface on the side the path arrives from
// (guided_surface_sampler.h), the leaf's indirect VMM (direction=incident) or its product with the
// cosine lobe (direction=product), with the BSDF probability the configuration or the learned
// selection sets, damped by the leaf's confidence. A pure BSDF sampler where there is nothing to guide
// with (not diffuse, no valid leaf, a leaf not mostly filled by a medium, surfaces not guided). One
// object per walk, owned by GuidedWalkPolicy: prepare() once per surface vertex, then pdf / sample.
#include <optional>

#include "volguide/integrators/guided/walk/guided_surface_sampler.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/vmm/vmm.h"

namespace volguide {

class SurfaceVertex {
  public:
    // The guide and `counts` (the walk's counters) must outlive the object.
    SurfaceVertex(const WalkGuide& guide, WalkGuideStats& counts) : guide_(guide), counts_(counts) {}
    // Whether the walk's camera sample is recorded for the allocation's learning (it explores then).
    void set_learning(bool learning) { learning_ = learning; }

    // The vertex si with its BSDF; `medium`: the one the path arrived through (null: none; its
    // extinction sets the leaf's confidence as in the medium). si and bsdf must outlive the decision.
    void prepare(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium);
    // The leaf beside the surface (-1: none), the learned selection's cell.
    int leaf() const { return leaf_; }
    // The mixture (a pure BSDF sampler when not guided); empty before prepare() or for a null BSDF.
    const std::optional<GuidedSurfaceSampler>& sampler() const { return sampler_; }
    // Whether the decision is unguided because the allocation's share is 0 (a guide could make it).
    bool guidable() const { return guidable_; }

  private:
    // The guide of leaf `index` beside the surface (normal n), or null.
    const Vmm* guide_of(int index, const Vec3f& n);

    const WalkGuide& guide_;
    WalkGuideStats& counts_;
    int leaf_ = -1;
    bool guidable_ = false, learning_ = false;
    std::optional<GuidedSurfaceSampler> sampler_;
    Vmm product_{Vmm::Uninitialized{}};  // the cosine product the sampler reads
};

}  // namespace volguide
