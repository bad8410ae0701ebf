#pragma once
// guided_volpath's policy for volpath's walk (walk_policy.h): it forwards every decision to the
// object that makes it — the distance and medium direction decisions to the vertex the ray leaves
// from (GuidedVertex, guided_vertex.h), the surface direction decision to SurfaceVertex
// (surface_vertex.h), guided RR and splitting against the pixel estimate I of the camera sample's
// pixel to GuidedContinuation (guided_continuation.h). Decisions the guide does not make are the
// unguided ones, with the same random numbers. One object per camera sample; it counts the walk's
// decisions (WalkGuideStats) and adds the counts to the guide's when it ends. What the walk records
// (the learners, Open PGL's path segments) is its PathRecorder's: the policy fills the DecisionRecord
// the walk hands it with each decision's mixture densities, and reports the continuation's estimate
// when asked.
#include <limits>
#include <utility>

#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/walk/guided_continuation.h"
#include "volguide/integrators/guided/walk/guided_vertex.h"
#include "volguide/integrators/guided/walk/surface_vertex.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

class GuidedWalkPolicy final : public WalkPolicy {
  public:
    // `rrs` null: no guided RR/splitting; `pixel`: I of the camera sample's pixel (> 0 with rrs);
    // `ears`: the pass's continuation statistics (rrs=ears, guided_continuation.h); `learning`: the
    // camera sample is recorded for the allocation (its decisions explore, allocation.h).
    GuidedWalkPolicy(const WalkGuide& guide, const RouletteSplitting* rrs, float pixel,
                     const ContinuationSnapshot* ears = nullptr, bool learning = false)
        : guide_(guide),
          continuation_(guide, rrs, pixel, ears),
          vertex_(guide, counts_),
          surface_(guide, counts_) {
        vertex_.set_learning(learning);
        surface_.set_learning(learning);
        continuation_.set_learning(learning);
    }
    ~GuidedWalkPolicy() override { guide_.add_stats(counts_); }
    GuidedWalkPolicy(const GuidedWalkPolicy&) = delete;
    GuidedWalkPolicy& operator=(const GuidedWalkPolicy&) = delete;

    // distance=vsp's camera segment (docs/theory.md §7.10.2): the first distance decision of the
    // camera sample, when the walk has no real event yet (depth 0: the camera ray, null surfaces
    // crossed, as the pixel estimate's buffer defines it) takes P_G = `guided` from the pixel's buffer
    // (NaN: none, the leaf's as elsewhere).
    void set_camera_segment(float guided) { camera_guided_ = guided; }

    bool guides_distance() const override { return guide_.guides_distance(); }
    FreeFlightSample sample_distance(const DistanceQuery& query, Sampler& sampler, DecisionRecord* record) override;

    void begin_vertex(const MediumInteraction& mi) override { vertex_.init(mi); }
    void end_vertex() override { vertex_.clear(); }
    int keep_vertex() override { return vertex_.keep(); }
    void resume_vertex(const MediumInteraction& mi, int kept) override { vertex_.resume(mi, kept); }

    void prepare_direction(const MediumInteraction& mi, Sampler& sampler) override { vertex_.prepare_direction(); }
    float direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const override { return vertex_.direction_pdf(wo); }
    PhaseSample sample_direction(const MediumInteraction& mi, Sampler& sampler, DecisionRecord* record) override;

    void prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                                   Sampler& sampler) override {
        surface_.prepare(si, bsdf, medium);
    }
    float surface_direction_pdf(const SurfaceQuery& at, const Vec3f& wo_local) const override;
    std::pair<BSDFSample, Color3> sample_surface_direction(const SurfaceQuery& at, float u1, Point2f u2,
                                                           Sampler& sampler, DecisionRecord* record) override;

    // At the current vertex (begin_vertex's: `mi` is its interaction).
    Continuation continuation(const ContinuationQuery& query, const MediumInteraction& mi, Sampler& sampler) override;
    bool decides_at_surfaces() const override { return continuation_.decides_at_surfaces(); }
    Continuation surface_continuation(const SurfaceInteraction& si, const ContinuationQuery& query,
                                      Sampler& sampler) override {
        return continuation_.decide_surface(si, query, sampler, vertex_.hint());
    }
    float branch_budget() const override { return continuation_.branch_budget(); }
    void end_camera_sample(int branches) override { continuation_.end_camera_sample(branches); }
    WorkCounts take_work() override { return std::exchange(counts_.work, WorkCounts{}); }

  private:
    const WalkGuide& guide_;
    GuidedContinuation continuation_;
    WalkGuideStats counts_;    // the walk's (before the vertex objects, which count into it)
    GuidedVertex vertex_;      // the medium vertex the ray leaves from (inactive: the camera, a surface)
    SurfaceVertex surface_;    // the current surface vertex's direction decision
    float camera_guided_ = std::numeric_limits<float>::quiet_NaN();  // until the first distance decision
};

}  // namespace volguide
