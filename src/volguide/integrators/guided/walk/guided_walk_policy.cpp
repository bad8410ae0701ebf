#include "volguide/integrators/guided/walk/guided_walk_policy.h"

namespace volguide {

FreeFlightSample GuidedWalkPolicy::sample_distance(const DistanceQuery& query, Sampler& sampler,
                                                   DecisionRecord* record) {
    if (!guide_.guides_distance()) return query.medium.sample_free_flight(query.ray, query.tmax, query.throughput, sampler);
    // The camera-ray buffer's P_G for the first decision only, and only before any real event.
    const float camera_guided = query.depth == 0 ? camera_guided_ : std::numeric_limits<float>::quiet_NaN();
    camera_guided_ = std::numeric_limits<float>::quiet_NaN();
    return vertex_.sample_distance(query, camera_guided, sampler, record);
}

Continuation GuidedWalkPolicy::continuation(const ContinuationQuery& query, const MediumInteraction&,
                                            Sampler& sampler) {
    const Continuation c = continuation_.decide(query, vertex_, sampler);
    if (query.stage == ContinuationStage::Distance && c.n == 0 && c.q != 1.f) ++counts_.vertex_distance_kills;
    return c;
}

PhaseSample GuidedWalkPolicy::sample_direction(const MediumInteraction& mi, Sampler& sampler,
                                               DecisionRecord* record) {
    if (record && vertex_.direction_guidable()) {  // unguided where the allocation's share is 0
        record->guidable = true;
        record->leaf = vertex_.leaf();
    }
    if (!vertex_.has_direction_sampler()) return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    const float u_strategy = sampler.next_1d();
    const GuidedDirectionSampler::Sample g = vertex_.sample_direction(sampler.next_2d(), u_strategy);
    ++counts_.direction_samples;
    counts_.direction_guided += g.guided;
    if (vertex_.guided()) counts_.work.add(Work::GuideEval);
    if (record && vertex_.guided() && g.pdf > 0.f) {
        *record = {true, vertex_.leaf(), g.pdf, mi.medium->phase().pdf(mi.wi, g.wo), vertex_.guide_pdf(g.wo)};
        counts_.work.add(Work::GuideEval);
    }
    PhaseSample ps;
    ps.wo = g.wo;
    ps.pdf = g.pdf;
    ps.weight = g.weight;
    return ps;
}

float GuidedWalkPolicy::surface_direction_pdf(const SurfaceQuery& at, const Vec3f& wo_local) const {
    return surface_.sampler() ? surface_.sampler()->pdf(at.ctx, wo_local) : at.bsdf.pdf(at.ctx, at.si, wo_local);
}

std::pair<BSDFSample, Color3> GuidedWalkPolicy::sample_surface_direction(const SurfaceQuery& at, float u1, Point2f u2,
                                                                         Sampler& sampler, DecisionRecord* record) {
    const auto& [ctx, si, bsdf] = at;
    const auto& s = surface_.sampler();
    if (record && surface_.guidable()) {  // unguided where the allocation's share is 0
        record->guidable = true;
        record->leaf = surface_.leaf();
    }
    if (!s || !s->guided()) return bsdf.sample(ctx, si, u1, u2);
    const GuidedSurfaceSampler::Sample g = s->sample(ctx, sampler.next_1d(), u1, u2);
    counts_.surface_guided_samples += g.guided;
    counts_.work.add(Work::GuideEval);
    if (record && g.bs.pdf > 0.f) {
        *record = {true, surface_.leaf(), g.bs.pdf, bsdf.pdf(ctx, si, g.bs.wo), s->guide_pdf(g.bs.wo)};
        counts_.work.add(Work::GuideEval);
    }
    return {g.bs, g.weight};
}

}  // namespace volguide
