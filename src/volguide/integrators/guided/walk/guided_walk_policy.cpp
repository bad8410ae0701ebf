#include "volguide/integrators/guided/walk/guided_walk_policy.h"

namespace volguide {

FreeFlightSample GuidedWalkPolicy::sample_distance(const Medium& medium, const Ray& ray, float tmax,
                                                   const Color3& throughput, Sampler& sampler, GuideRegion& region) {
    if (!guide_.guides_distance()) {
        if (recorder_) recorder_->unrecorded_decision();
        region = GuideRegion();  // the scattering vertex's is not known
        return medium.sample_free_flight(ray, tmax, throughput, sampler);
    }
    FreeFlightSample fs = guide_.sample_distance(medium, ray, tmax, throughput, sampler, region, scratch_);
    if (recorder_) {
        const DistanceScratch::Decision& d = scratch_.decision;
        if (d.mixture)
            recorder_->decision(SelectionDecision::Distance, d.leaf, d.pdf, d.p_u, d.p_g);
        else
            recorder_->unrecorded_decision();
    }
    return fs;
}

void GuidedWalkPolicy::prepare_direction(const MediumInteraction& mi, GuideRegion& region, Sampler&) {
    direction_.reset();
    if (guide_.guides_direction()) guide_.direction_sampler(mi, mi.medium->phase(), region, direction_);
    direction_leaf_ = region.leaf;
}

float GuidedWalkPolicy::direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const {
    return direction_ ? direction_->pdf(wo) : mi.medium->phase().pdf(mi.wi, wo);
}

PhaseSample GuidedWalkPolicy::sample_direction(const MediumInteraction& mi, Sampler& sampler) {
    if (!direction_) {
        if (recorder_) recorder_->unrecorded_decision();
        return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    }
    const float u_strategy = sampler.next_1d();
    const GuidedDirectionSampler::Sample g = direction_->sample(sampler.next_2d(), u_strategy);
    guide_.count_direction(g.guided);
    if (recorder_) {
        if (direction_->guided() && g.pdf > 0.f)
            recorder_->decision(SelectionDecision::Direction, direction_leaf_, g.pdf,
                                mi.medium->phase().pdf(mi.wi, g.wo), direction_->guide_pdf(g.wo));
        else
            recorder_->unrecorded_decision();
    }
    PhaseSample ps;
    ps.wo = g.wo;
    ps.pdf = g.pdf;
    ps.weight = g.weight;
    return ps;
}

void GuidedWalkPolicy::prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf,
                                                 const Medium* medium, Sampler&) {
    surface_.reset();
    surface_leaf_ = -1;
    if (guide_.guides_surfaces() && !bsdf.is_null())
        surface_leaf_ = guide_.surface_sampler(si, bsdf, medium, surface_guide_, surface_);
}

float GuidedWalkPolicy::surface_direction_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const BSDF& bsdf,
                                              const Vec3f& wo_local) const {
    return surface_ ? surface_->pdf(ctx, wo_local) : bsdf.pdf(ctx, si, wo_local);
}

std::pair<BSDFSample, Color3> GuidedWalkPolicy::sample_surface_direction(const BSDFContext& ctx,
                                                                         const SurfaceInteraction& si,
                                                                         const BSDF& bsdf, float u1, Point2f u2,
                                                                         Sampler& sampler) {
    if (!surface_ || !surface_->guided()) {
        if (recorder_) recorder_->unrecorded_decision();
        return bsdf.sample(ctx, si, u1, u2);
    }
    const GuidedSurfaceSampler::Sample g = surface_->sample(ctx, sampler.next_1d(), u1, u2);
    guide_.count_surface_direction(g.guided);
    if (recorder_) {
        if (g.bs.pdf > 0.f)
            recorder_->decision(SelectionDecision::Surface, surface_leaf_, g.bs.pdf, bsdf.pdf(ctx, si, g.bs.wo),
                                surface_->guide_pdf(g.bs.wo));
        else
            recorder_->unrecorded_decision();
    }
    return {g.bs, g.weight};
}

Continuation GuidedWalkPolicy::continuation(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                            const Color3& throughput, int branches, float allowance,
                                            Sampler& sampler, GuideRegion& region) {
    Continuation c;
    if (!rrs_ && !recorder_) return c;
    const Color3 estimate = stage == ContinuationStage::Distance ? guide_.inscattered_estimate(mi, w, region)
                                                                 : guide_.incident_estimate(mi, w, region);
    if (recorder_ && estimate.max_value() > 0.f)
        recorder_->continuation(int(stage), region.leaf, estimate.average(), throughput.average());
    if (!rrs_) return c;
    if (estimate.max_value() > 0.f && !guide_.rrs_acts(stage, region.leaf)) return c;  // learned: throughput RR
    c.guided = estimate.max_value() > 0.f;
    c.q = rrs_->factor(throughput, estimate, pixel_, branches, allowance);
    if (c.q == 1.f) return c;
    c.n = stochastic_round(c.q, sampler.next_1d());
    rrs_->count_outcome(c.n);
    return c;
}

float GuidedWalkPolicy::branch_budget() const {
    return rrs_ ? rrs_->initial_allowance() : std::numeric_limits<float>::infinity();
}

void GuidedWalkPolicy::end_camera_sample(int branches) {
    if (rrs_) rrs_->count_camera_sample(branches);
}

void GuidedWalkPolicy::record_contribution(const Color3& value) {
    if (recorder_) recorder_->contribution(value);
    if (training_) training_->record_contribution(value);
}

}  // namespace volguide
