#include "volguide/integrators/guided/walk/guided_walk_policy.h"

namespace volguide {

FreeFlightSample GuidedWalkPolicy::sample_distance(const Medium& medium, const Ray& ray, float tmax,
                                                   const Color3& throughput, Sampler& sampler,
                                                   VertexLeaf& scattering_leaf, DecisionRecord* record) {
    if (!guide_.guides_distance()) {
        scattering_leaf = VertexLeaf();  // the scattering vertex's is not known
        return medium.sample_free_flight(ray, tmax, throughput, sampler);
    }
    scratch_.record = record != nullptr;
    // The camera-ray buffer's P_G for the first decision only, and only along the camera ray.
    scratch_.camera_guided = ray.d == camera_d_ ? camera_guided_ : std::numeric_limits<float>::quiet_NaN();
    camera_guided_ = std::numeric_limits<float>::quiet_NaN();
    // The origin is the current vertex (its known leaf, and P_G its answer), none after a surface.
    FreeFlightSample fs = guide_.sample_distance(medium, ray, tmax, throughput, sampler,
                                                 vertex_.active() ? &vertex_ : nullptr, scattering_leaf, scratch_);
    const DistanceScratch::Decision& d = scratch_.decision;
    if (record) {
        if (d.mixture) *record = {true, d.leaf, d.pdf, d.p_u, d.p_g};
        record->leaf = d.leaf;  // the learned selection's per-method rounds count every decision
        record->lookups = int(d.lookups);
    }
    return fs;
}

void GuidedWalkPolicy::prepare_direction(const MediumInteraction&, Sampler&) { vertex_.prepare_direction(); }

Continuation GuidedWalkPolicy::continuation(ContinuationStage stage, const MediumInteraction&, const Vec3f& w,
                                            const Color3& throughput, int branches, float allowance, Sampler& sampler,
                                            bool report) {
    const Continuation c = continuation_.decide(stage, vertex_, w, throughput, branches, allowance, sampler, report);
    if (stage == ContinuationStage::Distance && c.n == 0 && c.q != 1.f) guide_.count_vertex_distance_kill();
    return c;
}

float GuidedWalkPolicy::direction_pdf(const MediumInteraction&, const Vec3f& wo) const {
    return vertex_.direction_pdf(wo);
}

PhaseSample GuidedWalkPolicy::sample_direction(const MediumInteraction& mi, Sampler& sampler,
                                               DecisionRecord* record) {
    if (!vertex_.has_direction_sampler()) return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    const float u_strategy = sampler.next_1d();
    const GuidedDirectionSampler::Sample g = vertex_.sample_direction(sampler.next_2d(), u_strategy);
    guide_.count_direction(g.guided);
    if (record && vertex_.guided() && g.pdf > 0.f)
        *record = {true, vertex_.leaf(), g.pdf, mi.medium->phase().pdf(mi.wi, g.wo), vertex_.guide_pdf(g.wo)};
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
                                                                         Sampler& sampler, DecisionRecord* record) {
    if (!surface_ || !surface_->guided()) return bsdf.sample(ctx, si, u1, u2);
    const GuidedSurfaceSampler::Sample g = surface_->sample(ctx, sampler.next_1d(), u1, u2);
    guide_.count_surface_direction(g.guided);
    if (record && g.bs.pdf > 0.f)
        *record = {true, surface_leaf_, g.bs.pdf, bsdf.pdf(ctx, si, g.bs.wo), surface_->guide_pdf(g.bs.wo)};
    return {g.bs, g.weight};
}

}  // namespace volguide
