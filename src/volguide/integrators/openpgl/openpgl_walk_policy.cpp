#include "volguide/integrators/openpgl/openpgl_walk_policy.h"

#include <cmath>

#include "volguide/integrators/openpgl/openpgl_version.h"
#include "volguide/integrators/openpgl/openpgl_vsp_distance.h"

namespace volguide {

namespace {

// Cycles does not guide nearly-delta phase functions: the product would be a spike the VMM cannot
// represent, and the phase function alone samples it perfectly.
constexpr float kMaxGuidedMeanCosine = 0.99f;

}  // namespace

OpenPglWalkPolicy::OpenPglWalkPolicy(const OpenPglSettings& settings, OpenPglThreadState& ts, OpenPglField& field)
    : settings_(settings), ts_(ts), field_(field) {}

FreeFlightSample OpenPglWalkPolicy::sample_distance(const DistanceQuery& query, Sampler& sampler, DecisionRecord*) {
    const float vsp = segment_vsp_;
    segment_vsp_ = std::numeric_limits<float>::quiet_NaN();  // one decision per segment
    ++ts_.distance_decisions;
    if (std::isnan(vsp)) return query.medium.sample_free_flight(query.ray, query.tmax, query.throughput, sampler);
    ++ts_.vsp_decisions;
    FreeFlightSample fs = openpgl_vsp_flight(query, vsp, settings_.vsp_unguided_prob, sampler);
    if (fs.scattered) ++ts_.vsp_scattered;
    return fs;
}

void OpenPglWalkPolicy::prepare_direction(const MediumInteraction& mi, Sampler& sampler) {
    volume_ready_ = false;
    segment_vsp_ = std::numeric_limits<float>::quiet_NaN();
    ++ts_.medium_vertices;
    if (!settings_.volume_guiding || settings_.phase_prob >= 1.f || !field_.trained()) return;
    const float g = mi.medium->phase().mean_cosine();
    if (!(std::abs(g) < kMaxGuidedMeanCosine)) return;
    float u = sampler.next_1d();  // Open PGL's stochastic choice among the nearest regions
    if (!ts_.volume.Init(&field_.field(), pgl_point(mi.p), u)) return;
    // The HG lobe about the propagation direction -wi (Open PGL's directions point towards the light).
    ts_.volume.ApplySingleLobeHenyeyGreensteinProduct(pgl_vec(-mi.wi), g);
    volume_ready_ = true;
    ++ts_.guided_medium;
}

float OpenPglWalkPolicy::direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const {
    const float p_phase = mi.medium->phase().pdf(mi.wi, wo);
    if (!volume_ready_) return p_phase;
    const float a = settings_.phase_prob;
    return a * p_phase + (1.f - a) * ts_.volume.PDF(pgl_vec(wo));
}

PhaseSample OpenPglWalkPolicy::sample_direction(const MediumInteraction& mi, Sampler& sampler, DecisionRecord*) {
    const PhaseFunction& phase = mi.medium->phase();
    if (!volume_ready_) return phase.sample(mi.wi, sampler.next_2d());
    const float u_strategy = sampler.next_1d();
    const Point2f u = sampler.next_2d();
    PhaseSample ps;
    ps.wo = u_strategy < settings_.phase_prob ? phase.sample(mi.wi, u).wo : normalize(from_pgl(ts_.volume.Sample(
                                                                              openpgl::cpp::Point2(u.x, u.y))));
    ps.pdf = direction_pdf(mi, ps.wo);
    if (!(ps.pdf > 0.f) || !std::isfinite(ps.pdf)) return PhaseSample{};
    ps.weight = phase.eval(mi.wi, ps.wo) / ps.pdf;
    if (settings_.vsp) segment_vsp_ = openpgl_volume_scatter_probability(ts_.volume, ps.wo);
    return ps;
}

void OpenPglWalkPolicy::prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium*,
                                                  Sampler& sampler) {
    surface_ready_ = false;
    if (bsdf.is_null()) return;  // a null crossing: not scattering; the ray's VSP (if any) is kept
    ++ts_.surface_vertices;
    segment_vsp_ = std::numeric_limits<float>::quiet_NaN();
    // Only diffuse reflectors: the cosine product stands for f cos of a Lambertian lobe.
    if (!settings_.surface_guiding || settings_.bsdf_prob >= 1.f || !field_.trained() ||
        bsdf.flags() != bsdf_flags::DiffuseReflection)
        return;
    float u = sampler.next_1d();
    if (!ts_.surface.Init(&field_.field(), pgl_point(si.p), u)) return;
    // The cosine lobe on the side the path arrived from (wi is local: z > 0 is the normal's side).
    const Vec3f n = si.sh_frame.n * (si.wi.z >= 0.f ? 1.f : -1.f);
    ts_.surface.ApplyCosineProduct(pgl_vec(n));
    surface_ready_ = true;
    ++ts_.guided_surface;
}

float OpenPglWalkPolicy::surface_direction_pdf(const SurfaceQuery& at, const Vec3f& wo_local) const {
    const float p_bsdf = at.bsdf.pdf(at.ctx, at.si, wo_local);
    if (!surface_ready_) return p_bsdf;
    const float b = settings_.bsdf_prob;
    return b * p_bsdf + (1.f - b) * ts_.surface.PDF(pgl_vec(at.si.to_world(wo_local)));
}

std::pair<BSDFSample, Color3> OpenPglWalkPolicy::sample_surface_direction(const SurfaceQuery& at, float u1, Point2f u2,
                                                                          Sampler& sampler, DecisionRecord*) {
    const auto& [ctx, si, bsdf] = at;
    if (!surface_ready_) return bsdf.sample(ctx, si, u1, u2);
    const float u_strategy = sampler.next_1d();
    BSDFSample bs;
    if (u_strategy < settings_.bsdf_prob) {
        const BSDFSample b = bsdf.sample(ctx, si, u1, u2).first;
        if (!(b.pdf > 0.f)) return {BSDFSample{}, Color3(0.f)};  // the BSDF failed (seen from behind)
        bs.wo = b.wo;
    } else {
        bs.wo = si.to_local(normalize(from_pgl(ts_.surface.Sample(openpgl::cpp::Point2(u2.x, u2.y)))));
    }
    bs.pdf = surface_direction_pdf(at, bs.wo);
    bs.eta = 1.f;
    bs.sampled_flags = bsdf_flags::DiffuseReflection;  // the only guided BSDF kind
    if (!(bs.pdf > 0.f) || !std::isfinite(bs.pdf)) return {BSDFSample{}, Color3(0.f)};
    if (settings_.vsp) segment_vsp_ = openpgl_volume_scatter_probability(ts_.surface, si.to_world(bs.wo));
    return {bs, bsdf.eval(ctx, si, bs.wo) * (1.f / bs.pdf)};
}

}  // namespace volguide
