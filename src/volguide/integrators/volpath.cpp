// Volumetric path tracer (Mitsuba 3's volpath semantics, see volpath.h).
//
// Equiangular sampling (setting `equiangular`), homogeneous media only. Per medium segment
// [0, tmax] of the ray o + t d, the direct light scattered once on the segment is the integral over
// (t, y), y a point on a light (for point/spot lights y is fixed), estimated by three strategies:
//   1. distance sampling t ~ p_d, then NEE y ~ p_nee(y | x_t)        density p1 = p_d(t) p_nee(y | x_t)
//   2. distance sampling, then phase sampling hits y (area lights)   density p2 = p_d(t) p_phase G
//   3. equiangular: y ~ p_E(y) (light sampled from o), t ~ p_e(t | y)  density p3 = p_E(y) p_e(t | y)
// with light densities in y's measure (area for area lights, the choice probability for delta lights)
// and G = |cos_y| / dist^2 converting the phase pdf. Each strategy is weighted by the power
// heuristic over all three, so the weights sum to one for every (t, y): unbiased. The distance
// sampler must expose its density for this, so in these segments the integrator samples the
// distance itself (homogeneous: one channel chosen in proportion to the throughput, mixture density over the channels,
// theory.md §2.6) instead of calling Medium::sample_free_flight. In heterogeneous media the
// integrator keeps plain free-flight sampling (preprocess warns): the tracking's density is not
// available in closed form there.
#include "volguide/integrators/volpath.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>
#include <tuple>

#include "volguide/core/log.h"
#include "volguide/integrators/equiangular.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/training_recorder.h"
#include "volguide/integrators/walk_guide.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/media/medium.h"
#include "volguide/media/spectral_mis.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

VolPathSettings VolPathSettings::from(const Properties& props) {
    VolPathSettings s;
    int64_t max_depth = props.get_int("max_depth", -1);
    if (max_depth < -1) props.fail_at("max_depth", "max_depth must be -1 (unbounded) or >= 0, got {}", max_depth);
    int64_t rr_depth = props.get_int("rr_depth", 5);
    if (rr_depth <= 0) props.fail_at("rr_depth", "rr_depth must be > 0, got {}", rr_depth);
    s.max_depth = int(max_depth);
    s.rr_depth = int(rr_depth);
    s.hide_emitters = props.get_bool("hide_emitters", false);
    s.equiangular = props.get_bool("equiangular", false);
    s.volume_only = props.get_bool("volume_only", false);
    s.forward_first_scatter = props.get_bool("forward_first_scatter", false);
    if (s.forward_first_scatter && s.equiangular)
        props.fail_at("forward_first_scatter", "volpath: forward_first_scatter cannot be combined with equiangular");
    return s;
}

std::string VolPathIntegrator::to_string() const {
    return fmt::format(
        "volpath[max_depth={}, rr_depth={}, hide_emitters={}, equiangular={}, volume_only={}, "
        "forward_first_scatter={}]",
        settings_.max_depth, settings_.rr_depth, settings_.hide_emitters, settings_.equiangular, settings_.volume_only,
        settings_.forward_first_scatter);
}

void VolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext&) {
    if (!settings_.equiangular) return;
    bool heterogeneous = scene.sensor().medium() && !scene.sensor().medium()->is_homogeneous();
    for (const auto& shape : scene.shapes())
        for (const Medium* m : {shape->interior_medium(), shape->exterior_medium()})
            if (m && !m->is_homogeneous()) heterogeneous = true;
    if (heterogeneous)
        warn({}, "volpath: equiangular sampling is only used in homogeneous media; heterogeneous media keep "
                 "distance sampling");
}

namespace {

// Emitters equiangular sampling can aim at: point, spot (a position) and area lights.
bool equiangular_target(const Emitter* e) {
    if (!e) return false;
    const uint32_t f = e->flags();
    if (f & emitter_flags::Surface) return true;
    return (f & emitter_flags::DeltaPosition) && !(f & emitter_flags::DeltaDirection);
}

// The segment of a homogeneous medium on which equiangular sampling runs, with the channel
// probabilities its distance sampling uses.
struct EquiSegment {
    Point3f o;
    Vec3f d;
    float tmax = 0.f;
    Color3 sigma_t, sigma_s;
    Color3 channel_probs{1.f / 3.f};
    float distance_pdf(float t) const { return spectral_distance_pdf(sigma_t, channel_probs, t); }
};

// Density of a light point y (record seen from `ref`) in y's measure: the area density for
// area lights, the choice probability for delta lights.
float light_point_density(const Scene& scene, const Interaction& ref, const DirectionSample& ds) {
    if (ds.delta) return 1.f / float(scene.emitters().size());
    const float cos_y = std::abs(dot(ds.d, ds.n));
    return scene.pdf_emitter_direction(ref, ds) * cos_y / (ds.dist * ds.dist);
}

// Record of the light point (p, n) seen from `x`.
DirectionSample record_towards(const Point3f& x, const DirectionSample& y) {
    DirectionSample ds = y;
    Vec3f d = y.p - x;
    ds.dist = norm(d);
    ds.d = d / ds.dist;
    return ds;
}

// p_E(y) * p_e(t | y) of the equiangular strategy for the light point y.
float equiangular_density(const Scene& scene, const EquiSegment& seg, const DirectionSample& y, float t) {
    if (!equiangular_target(y.emitter) || std::isinf(y.dist)) return 0.f;
    Interaction origin;
    origin.p = seg.o;
    const float p_light = light_point_density(scene, origin, record_towards(seg.o, y));
    if (!(p_light > 0.f)) return 0.f;
    return p_light * EquiangularSampler(seg.o, seg.d, seg.tmax, y.p).pdf(t);
}

float power3(float a, float b, float c) {
    // In double: squares of large finite pdfs overflow a float (see mis_power_heuristic).
    if (std::isinf(a)) return 1.f;
    if (std::isinf(b) || std::isinf(c)) return 0.f;
    const double a2 = double(a) * a, s = a2 + double(b) * b + double(c) * c;
    return s > 0.0 && std::isfinite(s) ? float(a2 / s) : 0.f;
}

// Radiance arriving at x from the light point y (record from x) times |cos_y| / dist^2, in y's
// measure: I / dist^2 for delta lights, L_e |cos_y| / dist^2 for area lights.
Color3 light_point_value(const DirectionSample& ds, const Interaction& x) {
    const Emitter& e = *ds.emitter;
    if (ds.delta) return e.sample_direction(x, Point2f(0.5f, 0.5f)).second;
    SurfaceInteraction si;
    si.p = ds.p;
    si.n = ds.n;
    si.t = 0.f;
    si.uv = ds.uv;
    si.sh_frame = Frame(ds.n);
    si.wi = si.to_local(-ds.d);
    si.shape = e.shape();
    return e.eval(si) * (std::abs(dot(ds.d, ds.n)) / (ds.dist * ds.dist));
}

}  // namespace

Color3 VolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const Ray& camera_ray) const {
    return Li(scene, sampler, camera_ray, nullptr);
}

Color3 VolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const Ray& camera_ray,
                             TrainingRecorder* recorder) const {
    return Li(scene, sampler, camera_ray, recorder, nullptr);
}

namespace {

// The state a path carries from one event to the next (everything but the pending intersection):
// what a split copy inherits.
struct WalkState {
    Color3 throughput{1.f};
    float eta = 1.f;
    Ray ray;
    const Medium* medium = nullptr;
    int depth = 0;             // real scattering events so far (null crossings do not count)
    int rr_depth_done = -1;    // Russian roulette is played once per depth
    int null_crossings = 0;
    bool specular_chain = false;  // the last real event was a delta lobe: emitter hits count fully
    Interaction last_vertex;   // last real scattering vertex and the pdf of the direction it sampled
    float last_pdf = 1.f;
    // Equiangular bookkeeping of the last medium vertex (for the MIS of phase-sampled hits).
    bool last_equi = false;
    EquiSegment last_seg;
    float last_t = 0.f, last_pd = 0.f;
};

// One branch of a camera sample's walk waiting on the stack (guided splitting): its state, its own
// random stream, and, for a split at a medium vertex before its NEE and direction, that vertex.
struct PendingBranch {
    WalkState state;
    Sampler sampler;
    bool at_vertex = false;  // resume at `mi` (NEE and direction), else trace state.ray
    MediumInteraction mi;
    bool equi = false;
    EquiSegment seg;
    float t_d = 0.f, pd = 0.f;
};

// Per-thread stack, reused across camera samples.
thread_local std::vector<PendingBranch> pending_branches;

}  // namespace

Color3 VolPathIntegrator::Li(const Scene& scene, Sampler& camera_sampler, const Ray& camera_ray,
                             TrainingRecorder* recorder, const WalkGuide* guide, const WalkSplitting* splitting) const {
    const VolPathSettings& s = settings_;
    const bool guide_distance = guide && guide->guides_distance();
    const bool guide_direction = guide && guide->guides_direction();
    // Guided RR/splitting (theory.md §9) needs the guide's estimates; training never uses it (its
    // recorder attributes contributions to one chain of vertices).
    const RouletteSplitting* rrs = splitting && guide ? splitting->rrs : nullptr;
    if (rrs && recorder) throw std::logic_error("volpath: guided RR/splitting cannot record training samples");
    auto depth_ok = [&](int d) { return s.max_depth < 0 || d < s.max_depth; };
    const BSDFContext ctx;

    Color3 result(0.f);
    // Every contribution goes through add(): the training recorder attributes it to the suffix of
    // the medium vertices recorded so far.
    auto add = [&](const Color3& c) {
        result += c;
        if (recorder) recorder->contribution(c);
    };
    WalkState state;
    state.ray = camera_ray;
    state.medium = scene.sensor().medium();
    // The walk below reads and writes the state through these names (a split copies `state`).
    Color3& throughput = state.throughput;
    float& eta = state.eta;
    Ray& ray = state.ray;
    const Medium*& medium = state.medium;
    int& depth = state.depth;
    int& rr_depth_done = state.rr_depth_done;
    int& null_crossings = state.null_crossings;
    bool& specular_chain = state.specular_chain;
    Interaction& last_vertex = state.last_vertex;
    float& last_pdf = state.last_pdf;
    bool& last_equi = state.last_equi;
    EquiSegment& last_seg = state.last_seg;
    float& last_t = state.last_t;
    float& last_pd = state.last_pd;

    SurfaceInteraction si;
    bool need_intersection = true;

    // The camera sample's first branch draws from the caller's sampler (so that without splitting
    // the walk is volpath's, number for number); split copies from streams forked off it.
    Sampler* rng = &camera_sampler;
    Sampler branch_sampler;
    int branches = 1;
    std::vector<PendingBranch>& stack = pending_branches;
    const size_t stack_base = stack.size();
    auto snapshot = [&](const Sampler& branch_rng) {
        PendingBranch b;
        b.state = state;
        b.sampler = branch_rng;
        return b;
    };
    // A guided RR/splitting decision with expected count q: false when the path ends; otherwise
    // the throughput carries 1/q and the n - 1 copies wait on the stack (made by `make_copy` with
    // their own random streams).
    auto roulette_split = [&](const Color3& estimate, auto&& make_copy) {
        const float q = rrs->factor(throughput, estimate, splitting->pixel, branches);
        if (q == 1.f) return true;
        const int n = stochastic_round(q, rng->next_1d());
        rrs->count_outcome(n);
        if (n == 0) return false;
        throughput *= 1.f / q;
        for (int k = 1; k < n; ++k) stack.push_back(make_copy(rng->fork(uint64_t(k))));
        branches += n - 1;
        return true;
    };

    // A real scattering event at the medium vertex mi (reached by `ray`): NEE and the next
    // direction. False when the path ends there.
    auto scatter = [&](const MediumInteraction& mi, bool equi, const EquiSegment& seg, float t_d, float pd) {
        const Medium& m = *mi.medium;
        const PhaseFunction& phase = m.phase();
        Sampler& sampler = *rng;

        if (s.forward_first_scatter && depth == 1) {
            // Inspection: a forward delta phase function at the first vertex (weight 1).
            specular_chain = true;
            last_vertex = mi;
            last_equi = false;
            ray = mi.spawn_ray(ray.d);
            need_intersection = true;
            return true;
        }
        // Guided directions (§8): one mixture per vertex, used by NEE's MIS and the continuation.
        std::optional<GuidedDirectionSampler> guided_dir;
        if (guide_direction) guide->direction_sampler(mi, phase, guided_dir);
        if (m.sample_emitters()) {
            specular_chain = false;
            VolumeEmitterSample es =
                sample_emitter_through_media(scene, mi, nullptr, medium, sampler.next_2d(), sampler);
            if (!es.weight.is_black()) {
                const float fp = phase.eval(mi.wi, es.ds.d);
                const float pp =
                    es.ds.delta ? 0.f : (guided_dir ? guided_dir->pdf(es.ds.d) : phase.pdf(mi.wi, es.ds.d));
                float w;
                if (equi && equiangular_target(es.ds.emitter) && !std::isinf(es.ds.dist)) {
                    const float p_nee = light_point_density(scene, mi, es.ds);
                    const float g = es.ds.delta ? 0.f : std::abs(dot(es.ds.d, es.ds.n)) / (es.ds.dist * es.ds.dist);
                    w = power3(pd * p_nee, pd * pp * g, equiangular_density(scene, seg, es.ds, t_d));
                } else {
                    w = es.ds.delta ? 1.f : mis_power_heuristic(es.ds.pdf, pp);
                }
                add(throughput * fp * es.weight * w);
                if (recorder) recorder->medium_nee(mi.p, es.ds.d, es.weight * w);
            }
        } else {
            specular_chain = true;
        }

        PhaseSample ps;
        if (guided_dir) {
            const float u_strategy = sampler.next_1d();
            const GuidedDirectionSampler::Sample g = guided_dir->sample(sampler.next_2d(), u_strategy);
            guide->count_direction(g.guided);
            ps.wo = g.wo;
            ps.pdf = g.pdf;
            ps.weight = g.weight;
        } else {
            ps = phase.sample(mi.wi, sampler.next_2d());
        }
        if (!(ps.pdf > 0.f)) return false;
        throughput *= ps.weight;
        // Training sample at x_j: the radiance arriving from w_j is what guides w_j.
        if (recorder) recorder->medium_vertex(mi.p, ps.wo, ps.pdf, throughput);
        last_vertex = mi;
        last_pdf = ps.pdf;  // MIS uses p_w alone: the direction stage's q depends on w (§8.3, §13.11)
        last_equi = equi;
        last_seg = seg;
        last_t = t_d;
        last_pd = pd;
        ray = mi.spawn_ray(ps.wo);
        need_intersection = true;
        // Direction-stage guided RR/splitting: the continuation along w_j collects ~ L~(x_j, w_j).
        if (rrs && !throughput.is_black()) {
            const Color3 estimate = guide->incident_estimate(mi, ps.wo);
            if (estimate.max_value() > 0.f) rr_depth_done = depth;  // replaces throughput RR at this depth
            if (!roulette_split(estimate, [&](const Sampler& r) { return snapshot(r); })) return false;
        }
        return true;
    };

    while (true) {       // the camera sample's branches
        while (true) {   // one branch's walk
            if (throughput.is_black()) break;
            if (depth > s.rr_depth && depth != rr_depth_done) {
                rr_depth_done = depth;
                const float q = std::min(throughput.max_value() * eta * eta, 0.95f);
                if (!(rng->next_1d() < q)) break;
                throughput *= 1.f / q;
            }
            if (!depth_ok(depth)) break;

            if (need_intersection) {
                if (!scene.intersect(ray, si)) si = miss_interaction(ray);
                need_intersection = false;
            }
            Sampler& sampler = *rng;

            if (medium) {
                const float tmax = si.is_valid() ? si.t : ray.tmax;
                const bool equi =
                    s.equiangular && !guide_distance && medium->is_homogeneous() && medium->sample_emitters();
                bool scattered = false;
                MediumInteraction mi;
                EquiSegment seg;
                float t_d = 0.f, pd = 0.f;

                if (equi) {
                    const MediumCoefficients mc = medium->eval(ray.o);
                    seg = {ray.o, ray.d, tmax, mc.sigma_t, mc.sigma_s, channel_probabilities(throughput)};
                    const Vec3f wi = -ray.d;

                    // Strategy 3: equiangular sample towards a light point chosen from the origin.
                    if (depth_ok(depth + 1)) {
                        Interaction origin;
                        origin.p = ray.o;
                        auto [ds_o, w_o] = scene.sample_emitter_direction(origin, sampler.next_2d(), false);
                        const float u = sampler.next_1d();
                        if (ds_o.pdf > 0.f && equiangular_target(ds_o.emitter)) {
                            const float p_light = light_point_density(scene, origin, ds_o);
                            EquiangularSampler eq(ray.o, ray.d, tmax, ds_o.p);
                            if (p_light > 0.f && eq.valid()) {
                                const float t = eq.sample(u), pe = eq.pdf(t);
                                Interaction x;
                                x.p = ray.o + ray.d * t;
                                x.t = t;
                                const DirectionSample ds = record_towards(x.p, ds_o);
                                const Color3 value = pe > 0.f ? light_point_value(ds, x) : Color3(0.f);
                                if (!value.is_black() && ds.dist > 0.f) {
                                    const PhaseFunction& phase = medium->phase();
                                    const float fp = phase.eval(wi, ds.d);
                                    const float p_d = seg.distance_pdf(t);
                                    const float p_nee = light_point_density(scene, x, ds);
                                    const float g = ds.delta ? 0.f : std::abs(dot(ds.d, ds.n)) / (ds.dist * ds.dist);
                                    const float p3 = p_light * pe;
                                    const float w = power3(p3, p_d * p_nee, p_d * phase.pdf(wi, ds.d) * g);
                                    if (w > 0.f && fp > 0.f) {
                                        const Color3 tr = shadow_transmittance(scene, x, medium, ds, sampler);
                                        add(throughput * transmittance_rgb(seg.sigma_t, t) * seg.sigma_s * fp * value *
                                            tr * (w / p3));
                                    }
                                }
                            }
                        }
                    }

                    // Distance sampling with the spectral-MIS mixture density (its pdf is needed for MIS).
                    float u = sampler.next_1d();
                    const int c = sample_channel(seg.channel_probs, u);
                    const float sc = seg.sigma_t[c];
                    const float t = sc > 0.f ? -std::log1p(-u) / sc : Infinity;
                    if (t < tmax) {
                        pd = seg.distance_pdf(t);
                        t_d = t;
                        throughput *= transmittance_rgb(seg.sigma_t, t) * seg.sigma_s * (1.f / pd);
                        scattered = true;
                        mi.p = ray.o + ray.d * t;
                        mi.t = t;
                        mi.wi = wi;
                        mi.coeffs = mc;
                        mi.medium = medium;
                    } else {
                        const Color3 tr = transmittance_rgb(seg.sigma_t, tmax);
                        const float p_escape = spectral_escape_probability(seg.sigma_t, seg.channel_probs, tmax);
                        throughput *= p_escape > 0.f ? tr * (1.f / p_escape) : Color3(0.f);
                    }
                } else {
                    FreeFlightSample ff = guide_distance
                                              ? guide->sample_distance(*medium, ray, tmax, throughput, sampler)
                                              : medium->sample_free_flight(ray, tmax, throughput, sampler);
                    throughput *= ff.weight;
                    scattered = ff.scattered;
                    if (scattered) mi = ff.mi;
                }

                if (scattered) {
                    if (throughput.is_black()) break;
                    ++depth;
                    if (!depth_ok(depth)) break;
                    if (!mi.medium) mi.medium = medium;
                    // Distance-stage guided RR/splitting: the vertex collects ~ L~_i(x_j, w_{j-1}) from
                    // here on; every copy does its own NEE and direction (§9.3).
                    if (rrs) {
                        const Color3 estimate = guide->inscattered_estimate(mi, ray.d);
                        if (estimate.max_value() > 0.f) rr_depth_done = depth;
                        const bool alive = roulette_split(estimate, [&](const Sampler& r) {
                            PendingBranch b = snapshot(r);
                            b.at_vertex = true;
                            b.mi = mi;
                            b.equi = equi;
                            b.seg = seg;
                            b.t_d = t_d;
                            b.pd = pd;
                            return b;
                        });
                        if (!alive) break;
                    }
                    if (!scatter(mi, equi, seg, t_d, pd)) break;
                    continue;
                }
                if (throughput.is_black()) break;
            }

            // The ray reached the surface si (or left the scene).
            // volume_only: a camera path whose first real event is not a medium scattering is excluded.
            if (s.volume_only && depth == 0 && !(si.is_valid() && si.shape->bsdf()->is_null())) break;
            const Emitter* emitter = si.is_valid() ? si.shape->emitter() : scene.environment();
            if (emitter && !(depth == 0 && (s.hide_emitters || s.volume_only))) {
                if (depth == 0 || specular_chain) {
                    add(throughput * emitter->eval(si));
                } else {
                    const DirectionSample ds = emitter_hit_record(si, last_vertex, ray.d, emitter);
                    const float emitter_pdf = scene.pdf_emitter_direction(last_vertex, ds);
                    float w;
                    if (last_equi && equiangular_target(emitter) && !std::isinf(ds.dist)) {
                        const float g = std::abs(dot(ds.d, ds.n)) / (ds.dist * ds.dist);
                        w = power3(last_pd * last_pdf * g, last_pd * emitter_pdf * g,
                                   equiangular_density(scene, last_seg, ds, last_t));
                    } else {
                        w = mis_power_heuristic(last_pdf, emitter_pdf);
                    }
                    add(throughput * emitter->eval(si) * w);
                }
            }
            if (!si.is_valid()) break;

            const BSDF& bsdf = *si.shape->bsdf();
            // Guided surface directions: one mixture per vertex, used by NEE's MIS and the continuation.
            std::optional<GuidedSurfaceSampler> surface_dir;
            Vmm surface_guide{Vmm::Uninitialized{}};
            if (guide && guide->guides_surfaces() && !bsdf.is_null())
                guide->surface_sampler(si, bsdf, medium, surface_guide, surface_dir);
            // NEE (only when its path, one segment longer, is within max_depth).
            if (bsdf.has(bsdf_flags::Smooth) && depth_ok(depth + 1)) {
                VolumeEmitterSample es =
                    sample_emitter_through_media(scene, si, &si, medium, sampler.next_2d(), sampler);
                if (!es.weight.is_black()) {
                    const Vec3f wo = si.to_local(es.ds.d);
                    const Color3 f = bsdf.eval(ctx, si, wo);
                    const float bsdf_pdf =
                        es.ds.delta ? 0.f : (surface_dir ? surface_dir->pdf(ctx, wo) : bsdf.pdf(ctx, si, wo));
                    const float w = es.ds.delta ? 1.f : mis_power_heuristic(es.ds.pdf, bsdf_pdf);
                    add(throughput * f * es.weight * w);
                }
            }

            const float u1 = sampler.next_1d();
            const Point2f u2 = sampler.next_2d();
            BSDFSample bs;
            Color3 bsdf_weight;
            if (surface_dir && surface_dir->guided()) {
                const GuidedSurfaceSampler::Sample g = surface_dir->sample(ctx, sampler.next_1d(), u1, u2);
                guide->count_surface_direction(g.guided);
                bs = g.bs;
                bsdf_weight = g.weight;
            } else {
                std::tie(bs, bsdf_weight) = bsdf.sample(ctx, si, u1, u2);
            }
            throughput *= bsdf_weight;
            if (throughput.is_black()) break;
            eta *= bs.eta;
            const Vec3f wo = si.to_world(bs.wo);
            if (bs.sampled_flags & bsdf_flags::Null) {
                if (++null_crossings > 1024) break;  // a ray stuck on a surface
            } else {
                ++depth;
                last_vertex = si;
                last_pdf = bs.pdf;
                last_equi = false;
                specular_chain = (bs.sampled_flags & bsdf_flags::Delta) != 0;
            }
            medium = medium_after(si, wo, medium);
            ray = si.spawn_ray(wo);
            need_intersection = true;
        }

        // The next waiting branch of this camera sample, if any.
        if (stack.size() == stack_base) break;
        PendingBranch b = std::move(stack.back());
        stack.pop_back();
        state = b.state;
        branch_sampler = b.sampler;
        rng = &branch_sampler;
        need_intersection = true;
        if (b.at_vertex && !scatter(b.mi, b.equi, b.seg, b.t_d, b.pd)) throughput = Color3(0.f);  // ended there
    }
    if (rrs) rrs->count_camera_sample(branches);
    return result;
}

}  // namespace volguide
