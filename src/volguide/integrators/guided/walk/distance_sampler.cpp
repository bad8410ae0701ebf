#include "volguide/integrators/guided/walk/distance_sampler.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "volguide/guiding/guided_collision.h"
#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/integrators/guided/walk/vsp_distance.h"
#include "volguide/media/majorant_tracking.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

namespace {

// The medium's own free flight from the origin's leaf, kept as the scattering vertex's where it
// holds the point (deep in a dense medium it usually does: the direction decision needs no descent).
class FreeFlightDistance final : public DistanceSampler {
  public:
    using DistanceSampler::DistanceSampler;
    FreeFlightSample sample(const DistanceQuery& q, const DistanceInput& in, DistanceScratch&, Sampler& sampler,
                            DistanceOutcome& out) const override {
        FreeFlightSample fs = q.medium.sample_free_flight(q.ray, q.tmax, q.throughput, sampler);
        if (in.origin >= 0 && fs.scattered && in.field.field->tree().holds_point(in.origin, fs.mi.p))
            out.scattering = in.origin;
        return fs;
    }
};

// The incremental product sampler over the bins of (0, t_end), t_end where the ray leaves the field
// or tmax, then the medium's own free flight beyond the field; guided tracking in media that track
// null collisions.
class IncrementalDistance final : public DistanceSampler {
  public:
    using DistanceSampler::DistanceSampler;
    FreeFlightSample sample(const DistanceQuery& q, const DistanceInput& in, DistanceScratch& scratch, Sampler& sampler,
                            DistanceOutcome& out) const override {
        const GuidingField& field = *in.field.field;
        float b0, b1;
        const bool crosses = !field.empty() && field.tree().bounds().ray_intersect(q.ray, b0, b1) && b1 > 0.f;
        const float t_end = crosses ? std::min(q.tmax, b1) : 0.f;
        if (!(t_end > 0.f) || !std::isfinite(t_end)) {
            out.report.method = DistanceReport::Method::OutsideField;
            return q.medium.sample_free_flight(q.ray, q.tmax, q.throughput, sampler);
        }
        const float c_T = 1.f - in.share.undamped;  // the bins damp by their own leaves' confidence
        if (q.medium.tracks_null_collisions()) return tracked(q, in.field, c_T, t_end, sampler, out.report);
        const Segment segment{q, in, t_end, c_T};
        return binned(segment, scratch, sampler, out);
    }

  private:
    // Guided null-collision tracking over the whole segment: beyond the field the tracking falls back
    // to the unguided probability.
    FreeFlightSample tracked(const DistanceQuery& q, const PhaseField& at, float c_T, float t_end, Sampler& sampler,
                             DistanceReport& report) const {
        GuidedCollisionProbability probability(*at.field, at.estimates, q.ray, t_end, c_T);
        FreeFlightSample fs = guided_tracking(q.medium, q.ray, q.tmax, q.throughput, sampler, probability);
        report = {DistanceReport::Method::Tracking, uint64_t(probability.collisions()),
                  uint64_t(probability.unguided_collisions()), 0, uint64_t(probability.nan_fallbacks())};
        return fs;
    }

    // The bins' segment: the query up to t_end, with the decision's unguided share c_T.
    struct Segment {
        const DistanceQuery& q;
        const DistanceInput& in;
        float t_end, c_T;
    };

    FreeFlightSample binned(const Segment& segment, DistanceScratch& scratch, Sampler& sampler,
                            DistanceOutcome& out) const {
        const DistanceQuery& q = segment.q;
        const float t_end = segment.t_end;
        const PhaseField& at = segment.in.field;
        GuidedDistanceSettings settings = settings_.bins;
        settings.c_T = segment.c_T;
        settings.channel_split = channel_probabilities(q.throughput);  // spectral MIS (§2.6)
        const LeafGroups* groups = at.groups;
        const BinField bins{*at.field, at.estimates, groups, *at.leaf_extent, settings_.max_bin_optical_depth,
                            settings_.leaf_tau_max};
        BinsReport bins_report;
        const DistanceSample ds = sample_bins(segment, bins, scratch, sampler, settings, bins_report);
        out.report = {DistanceReport::Method::Bins, uint64_t(ds.steps), bins_report.invalid, bins_report.damped,
                      uint64_t(ds.nan_fallbacks), ds.strategy == DistanceStrategy::Guided};
        const int leaf = bins_report.leaf;
        if (ds.event == DistanceEvent::Medium && ds.pdf > 0.f)
            out.scattering = groups && leaf >= 0 ? groups->fine_leaf(leaf, q.ray(ds.t)) : leaf;
        if (ds.pdf > 0.f && ds.pdf_transmittance >= 0.f && ds.pdf_guided >= 0.f)
            out.record = {true, segment.in.origin, ds.pdf, ds.pdf_transmittance, ds.pdf_guided};
        return weighted(q, t_end, ds, sampler);
    }

    // The incremental sampler over the segment's bins: fused with the leaf walk in a medium of one proxy
    // with tabulated estimates (every homogeneous medium of constant albedo), else over BinSource.
    static DistanceSample sample_bins(const Segment& segment, const BinField& bins, DistanceScratch& scratch,
                                      Sampler& sampler, const GuidedDistanceSettings& settings, BinsReport& report) {
        const DistanceQuery& q = segment.q;
        ProxySegment proxy;
        if (bins.estimates && bins.estimates->resolution() > 0 && q.medium.constant_proxy(proxy))
            return sample_constant_bins({q.ray, segment.t_end, proxy, bins, segment.in.origin}, sampler, settings,
                                        report);
        BinSource source(q.ray, segment.t_end, q.medium, bins, scratch.proxies, segment.in.origin);
        const DistanceSample ds = sample_incremental_distance(source, sampler, settings);
        report = {source.leaf(), source.invalid(), source.damped()};
        return ds;
    }

    // The weights of the bins' decision `ds` (the caller contract of guided_distance.h), and beyond
    // the field (t_end < tmax) the medium's own free flight.
    static FreeFlightSample weighted(const DistanceQuery& q, float t_end, const DistanceSample& ds, Sampler& sampler) {
        const Medium& medium = q.medium;
        FreeFlightSample fs;
        if (ds.event == DistanceEvent::Medium && ds.pdf > 0.f) {
            const Color3 tr = medium.transmittance(q.ray, ds.t, sampler);
            const Point3f p = q.ray(ds.t);
            fs.scatter_at(q.ray, ds.t, p, &medium, medium.eval(p));
            fs.flight_weight = tr * (1.f / ds.pdf);
            fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
            return fs;
        }
        if (ds.event == DistanceEvent::Medium || !(ds.pdf > 0.f)) {  // a zero pdf cannot be weighted: no path
            fs.weight = fs.flight_weight = Color3(0.f);
            fs.t = t_end;
            return fs;
        }
        const Color3 tr = medium.transmittance(q.ray, t_end, sampler);
        fs.weight = fs.flight_weight = tr * (1.f / ds.pdf);
        fs.t = t_end;
        if (!(t_end < q.tmax)) return fs;
        // Beyond the field: ordinary free flight from the exit point.
        const Ray rest(q.ray(t_end), q.ray.d);
        FreeFlightSample tail = medium.sample_free_flight(rest, q.tmax - t_end, q.throughput * fs.weight, sampler);
        tail.weight *= fs.weight;
        tail.flight_weight *= fs.weight;
        tail.t += t_end;
        if (tail.scattered) {
            tail.mi.t = tail.t;
            tail.mi.wi = -q.ray.d;
        }
        return tail;
    }
};

// One decision per segment from the origin's leaf: in closed form in homogeneous media, by resampling
// the segment's tentative collisions otherwise.
class VspDistance final : public DistanceSampler {
  public:
    using DistanceSampler::DistanceSampler;
    FreeFlightSample sample(const DistanceQuery& q, const DistanceInput& in, DistanceScratch&, Sampler& sampler,
                            DistanceOutcome& out) const override {
        out.report.method = DistanceReport::Method::Vsp;
        out.report.camera = in.camera();
        return q.medium.is_homogeneous() ? closed_form(q, in, sampler, out) : resampled(q, in, sampler, out);
    }

  private:
    // distance=vsp's least unguided share: P stays above a tenth of free flight's where the field
    // says nothing scatters (a leaf's estimate is one value for a whole segment).
    static constexpr float kMinUnguided = 0.1f;

    // The defensive unguided share of the mixture (§7.10): at least kMinUnguided, 1 - the guided share
    // (damped by the origin leaf's confidence; the camera buffer's P_G has no leaf).
    static float unguided_share(const DistanceInput& in) { return std::max(1.f - in.share.share, kMinUnguided); }

    FreeFlightSample closed_form(const DistanceQuery& q, const DistanceInput& in, Sampler& sampler,
                                 DistanceOutcome& out) const {
        const Medium& medium = q.medium;
        const MediumCoefficients at_origin = medium.eval(q.ray.o);
        const HomogeneousVsp vsp(at_origin.sigma_t, q.tmax, channel_probabilities(q.throughput));
        const float st = at_origin.sigma_t.average();
        const float albedo = st > 0.f ? at_origin.sigma_s.average() / st : 0.f;  // shapes P_G only
        const float guided =
            in.camera() ? in.camera_guided : in.field.scatter_probability(in.origin, q.ray.d, albedo, vsp.unguided());
        if (std::isnan(guided)) {
            out.report.unguided = true;
            return medium.sample_free_flight(q.ray, q.tmax, q.throughput, sampler);  // the same decision, unguided
        }
        const float P = vsp.probability(guided, unguided_share(in));
        const float u_decide = sampler.next_1d(), u_channel = sampler.next_1d(), u_t = sampler.next_1d();
        // The equiangular share (§7.10.1): a light point drawn only for a scatter (2 numbers).
        const float share = settings_.vsp_equiangular;
        std::optional<EquiangularSampler> toward_light;
        if (u_decide < P && share > 0.f && medium.sample_emitters())
            toward_light = vsp_equiangular_toward_light(scene_, q.ray, q.tmax, sampler);
        const VspEquiangular equi{toward_light ? &*toward_light : nullptr, share};
        const HomogeneousVsp::Sample vs = vsp.sample(P, u_decide, u_channel, u_t, equi);
        out.report.equiangular = vs.scattered && equi.active();
        out.report.scattered = vs.scattered;
        FreeFlightSample fs;
        fs.t = vs.t;
        fs.weight = fs.flight_weight = vs.flight_weight;
        if (vs.scattered) {
            const Point3f p = q.ray(vs.t);
            fs.scatter_at(q.ray, vs.t, p, &medium, medium.eval(p));
            fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
            if (in.field.field->tree().holds_point(in.origin, p)) out.scattering = in.origin;
        }
        // The mixture's parts for the selection pilot: the density (or probability) of the outcome
        // under the unguided and the guided decision.
        const float cond = vs.scattered ? vsp.conditional_pdf(vs.t, equi) : 1.f;
        const float pu = vs.scattered ? vsp.unguided() * cond : 1.f - vsp.unguided();
        const float pg = vs.scattered ? guided * cond : 1.f - guided;
        if (vs.pdf > 0.f && P < 1.f) out.record = {true, in.origin, vs.pdf, pu, pg};
        return fs;
    }

    FreeFlightSample resampled(const DistanceQuery& q, const DistanceInput& in, Sampler& sampler,
                               DistanceOutcome& out) const {
        const Medium& medium = q.medium;
        // The albedo field at the origin (the extinction there may be 0 on the medium's boundary).
        const float albedo = medium.albedo(q.ray.o).average();  // shapes P_G only
        const PhaseField& at = in.field;
        if (!in.camera() && std::isnan(at.scatter_probability(in.origin, q.ray.d, albedo, 1.f))) {
            out.report.unguided = true;
            return medium.sample_free_flight(q.ray, q.tmax, q.throughput, sampler);
        }
        out.report.resampled = true;
        const float c = unguided_share(in);
        auto probability = [&](float unguided) {
            if (in.camera()) return c * unguided + (1.f - c) * in.camera_guided;
            const float guided = at.scatter_probability(in.origin, q.ray.d, albedo, unguided);
            return std::isnan(guided) ? unguided : c * unguided + (1.f - c) * guided;
        };
        FreeFlightSample fs = resampled_segment_flight(medium, q.ray, q.tmax, q.throughput, probability, sampler);
        out.report.scattered = fs.scattered;
        if (fs.scattered) {
            if (at.field->tree().holds_point(in.origin, fs.mi.p)) out.scattering = in.origin;
        }
        return fs;
    }
};

}  // namespace

std::unique_ptr<DistanceSampler> make_distance_sampler(DistanceGuiding method, const DistanceSettings& settings,
                                                       const Scene& scene) {
    switch (method) {
        case DistanceGuiding::Incremental: return std::make_unique<IncrementalDistance>(settings, scene);
        case DistanceGuiding::Vsp: return std::make_unique<VspDistance>(settings, scene);
        case DistanceGuiding::Standard: break;
    }
    return std::make_unique<FreeFlightDistance>(settings, scene);
}

}  // namespace volguide
