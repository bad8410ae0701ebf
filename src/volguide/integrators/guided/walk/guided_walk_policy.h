#pragma once
// guided_volpath's policy for volpath's walk (walk_policy.h): the guiding field's distance and
// direction decisions (WalkGuide, walk_guide.h) and, with a RouletteSplitting, guided RR and
// splitting against the pixel estimate I of the camera sample's pixel (roulette_splitting.h).
// Decisions the guide does not make are the analog ones, with the same random numbers. One object
// per camera sample (it holds the vertex's prepared samplers and the distance decisions' scratch).
// With a SelectionRecorder (the learned selection's pilot, selection_pilot.h) it also records every
// decision's mixture densities, the continuation points and the contributions. With a training
// recorder (training_recorder.h) it hands it the medium vertices (with the guided densities their
// directions were sampled with), their NEE samples, the contributions and the split copies.
#include <optional>

#include "volguide/guiding/guided_direction.h"
#include "volguide/integrators/guided/walk/guided_surface_sampler.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/estimates/selection_pilot.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/vmm/vmm.h"

namespace volguide {

class GuidedWalkPolicy final : public WalkPolicy {
  public:
    // `rrs` null: no guided RR/splitting; `pixel`: I of the camera sample's pixel (> 0 with rrs).
    // `recorder`: the selection pilot's (null: none).
    GuidedWalkPolicy(const WalkGuide& guide, const RouletteSplitting* rrs, float pixel,
                     SelectionRecorder* recorder = nullptr)
        : guide_(guide), rrs_(rrs), pixel_(pixel), recorder_(recorder) {
        scratch_.record = recorder != nullptr;
    }

    bool guides_distance() const override { return guide_.guides_distance(); }
    FreeFlightSample sample_distance(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                     Sampler& sampler, GuideRegion& region) override;

    void prepare_direction(const MediumInteraction& mi, GuideRegion& region, Sampler& sampler) override;
    float direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const override;
    PhaseSample sample_direction(const MediumInteraction& mi, Sampler& sampler) override;

    void prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                                   Sampler& sampler) override;
    float surface_direction_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const BSDF& bsdf,
                                const Vec3f& wo_local) const override;
    std::pair<BSDFSample, Color3> sample_surface_direction(const BSDFContext& ctx, const SurfaceInteraction& si,
                                                           const BSDF& bsdf, float u1, Point2f u2,
                                                           Sampler& sampler) override;

    float branch_budget() const override;
    Continuation continuation(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                              const Color3& throughput, int branches, float allowance, Sampler& sampler,
                              GuideRegion& region) override;
    void end_camera_sample(int branches) override;
    void record_contribution(const Color3& value) override;

    // Also record training samples into `training` (null: none).
    void record_training(WalkPolicy* training) { training_ = training; }
    void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) override {
        if (training_) training_->record_medium_vertex(x, w, pdf, throughput);
    }
    void record_medium_nee(const Point3f& x, const Vec3f& d, const Color3& weight) override {
        if (training_) training_->record_medium_nee(x, d, weight);
    }
    int branch_point() override { return training_ ? training_->branch_point() : 0; }
    void resume_branch(int point) override {
        if (training_) training_->resume_branch(point);
    }

  private:
    const WalkGuide& guide_;
    const RouletteSplitting* rrs_;
    float pixel_;
    SelectionRecorder* recorder_;
    WalkPolicy* training_ = nullptr;
    DistanceScratch scratch_;
    int direction_leaf_ = -1;  // the current medium vertex's leaf (-1: none), for the recorder
    int surface_leaf_ = -1;    // the leaf beside the current surface vertex
    std::optional<GuidedDirectionSampler> direction_;  // of the current medium vertex
    std::optional<GuidedSurfaceSampler> surface_;      // of the current surface vertex
    Vmm surface_guide_{Vmm::Uninitialized{}};          // the product guide surface_ reads
};

}  // namespace volguide
