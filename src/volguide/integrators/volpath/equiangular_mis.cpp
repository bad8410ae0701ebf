#include "volguide/integrators/volpath/equiangular_mis.h"

#include <cmath>

#include "volguide/integrators/volpath/equiangular.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {

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

// |cos_y| / dist^2 of a light point record (0 for delta lights).
float geometry_term(const DirectionSample& ds) {
    return ds.delta ? 0.f : std::abs(dot(ds.d, ds.n)) / (ds.dist * ds.dist);
}

}  // namespace

bool equiangular_target(const Emitter* e) {
    if (!e) return false;
    const uint32_t f = e->flags();
    if (f & emitter_flags::Surface) return true;
    return (f & emitter_flags::DeltaPosition) && !(f & emitter_flags::DeltaDirection);
}

EquiSegment equiangular_segment(const Ray& ray, float tmax, const MediumCoefficients& mc, const Color3& throughput) {
    return {ray.o, ray.d, tmax, mc.sigma_t, mc.sigma_s, channel_probabilities(throughput)};
}

std::optional<Color3> equiangular_light_sample(const Scene& scene, const Medium& medium, const EquiSegment& seg,
                                               const Color3& throughput, Sampler& sampler) {
    Interaction origin;
    origin.p = seg.o;
    auto [ds_o, w_o] = scene.sample_emitter_direction(origin, sampler.next_2d(), false);
    const float u = sampler.next_1d();
    if (!(ds_o.pdf > 0.f) || !equiangular_target(ds_o.emitter)) return std::nullopt;
    const float p_light = light_point_density(scene, origin, ds_o);
    EquiangularSampler eq(seg.o, seg.d, seg.tmax, ds_o.p);
    if (!(p_light > 0.f) || !eq.valid()) return std::nullopt;
    const float t = eq.sample(u), pe = eq.pdf(t);
    Interaction x;
    x.p = seg.o + seg.d * t;
    x.t = t;
    const DirectionSample ds = record_towards(x.p, ds_o);
    const Color3 value = pe > 0.f ? light_point_value(ds, x) : Color3(0.f);
    if (value.is_black() || !(ds.dist > 0.f)) return std::nullopt;
    const Vec3f wi = -seg.d;
    const PhaseFunction& phase = medium.phase();
    const float fp = phase.eval(wi, ds.d);
    const float p_d = seg.distance_pdf(t);
    const float p_nee = light_point_density(scene, x, ds);
    const float g = geometry_term(ds);
    const float p3 = p_light * pe;
    const float w = power3(p3, p_d * p_nee, p_d * phase.pdf(wi, ds.d) * g);
    if (!(w > 0.f && fp > 0.f)) return std::nullopt;
    const Color3 tr = shadow_transmittance(scene, x, &medium, ds, sampler);
    return throughput * transmittance_rgb(seg.sigma_t, t) * seg.sigma_s * fp * value * tr * (w / p3);
}

FreeFlightSample equiangular_free_flight(const Ray& ray, const EquiSegment& seg, const MediumCoefficients& mc,
                                         const Medium* medium, Sampler& sampler, EquiVertex& vertex) {
    FreeFlightSample fs;
    float u = sampler.next_1d();
    const int c = sample_channel(seg.channel_probs, u);
    const float sc = seg.sigma_t[c];
    const float t = sc > 0.f ? -std::log1p(-u) / sc : Infinity;
    if (t < seg.tmax) {
        const float pd = seg.distance_pdf(t);
        fs.weight = transmittance_rgb(seg.sigma_t, t) * seg.sigma_s * (1.f / pd);
        fs.scatter_at(ray, t, ray.o + ray.d * t, medium, mc);
        vertex = {true, seg, t, pd};
    } else {
        const Color3 tr = transmittance_rgb(seg.sigma_t, seg.tmax);
        const float p_escape = spectral_escape_probability(seg.sigma_t, seg.channel_probs, seg.tmax);
        fs.weight = p_escape > 0.f ? tr * (1.f / p_escape) : Color3(0.f);
        vertex = {true, seg, 0.f, 0.f};
    }
    return fs;
}

bool equiangular_mis_applies(const EquiVertex& v, const DirectionSample& ds) {
    return v.on && equiangular_target(ds.emitter) && !std::isinf(ds.dist);
}

float equiangular_nee_weight(const Scene& scene, const Interaction& x, const EquiVertex& v, const DirectionSample& ds,
                             float pp) {
    const float p_nee = light_point_density(scene, x, ds);
    const float g = geometry_term(ds);
    return power3(v.pd * p_nee, v.pd * pp * g, equiangular_density(scene, v.seg, ds, v.t));
}

float equiangular_hit_weight(const Scene& scene, const EquiVertex& v, const DirectionSample& ds, float last_pdf,
                             float emitter_pdf) {
    const float g = std::abs(dot(ds.d, ds.n)) / (ds.dist * ds.dist);
    return power3(v.pd * last_pdf * g, v.pd * emitter_pdf * g, equiangular_density(scene, v.seg, ds, v.t));
}

}  // namespace volguide
