#include "volguide/integrators/guided_walk_policy.h"

namespace volguide {

FreeFlightSample GuidedWalkPolicy::sample_distance(const Medium& medium, const Ray& ray, float tmax,
                                                   const Color3& throughput, Sampler& sampler, GuideRegion& region) {
    if (guide_.guides_distance())
        return guide_.sample_distance(medium, ray, tmax, throughput, sampler, region, scratch_);
    region = GuideRegion();  // the scattering vertex's is not known
    return medium.sample_free_flight(ray, tmax, throughput, sampler);
}

void GuidedWalkPolicy::prepare_direction(const MediumInteraction& mi, GuideRegion& region, Sampler&) {
    direction_.reset();
    if (guide_.guides_direction()) guide_.direction_sampler(mi, mi.medium->phase(), region, direction_);
}

float GuidedWalkPolicy::direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const {
    return direction_ ? direction_->pdf(wo) : mi.medium->phase().pdf(mi.wi, wo);
}

PhaseSample GuidedWalkPolicy::sample_direction(const MediumInteraction& mi, Sampler& sampler) {
    if (!direction_) return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    const float u_strategy = sampler.next_1d();
    const GuidedDirectionSampler::Sample g = direction_->sample(sampler.next_2d(), u_strategy);
    guide_.count_direction(g.guided);
    PhaseSample ps;
    ps.wo = g.wo;
    ps.pdf = g.pdf;
    ps.weight = g.weight;
    return ps;
}

void GuidedWalkPolicy::prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf,
                                                 const Medium* medium, Sampler&) {
    surface_.reset();
    if (guide_.guides_surfaces() && !bsdf.is_null()) guide_.surface_sampler(si, bsdf, medium, surface_guide_, surface_);
}

float GuidedWalkPolicy::surface_direction_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const BSDF& bsdf,
                                              const Vec3f& wo_local) const {
    return surface_ ? surface_->pdf(ctx, wo_local) : bsdf.pdf(ctx, si, wo_local);
}

std::pair<BSDFSample, Color3> GuidedWalkPolicy::sample_surface_direction(const BSDFContext& ctx,
                                                                         const SurfaceInteraction& si,
                                                                         const BSDF& bsdf, float u1, Point2f u2,
                                                                         Sampler& sampler) {
    if (!surface_ || !surface_->guided()) return bsdf.sample(ctx, si, u1, u2);
    const GuidedSurfaceSampler::Sample g = surface_->sample(ctx, sampler.next_1d(), u1, u2);
    guide_.count_surface_direction(g.guided);
    return {g.bs, g.weight};
}

Continuation GuidedWalkPolicy::continuation(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                            const Color3& throughput, int branches, float allowance,
                                            Sampler& sampler, GuideRegion& region) {
    Continuation c;
    if (!rrs_) return c;
    const Color3 estimate = stage == ContinuationStage::Distance ? guide_.inscattered_estimate(mi, w, region)
                                                                 : guide_.incident_estimate(mi, w, region);
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

}  // namespace volguide
