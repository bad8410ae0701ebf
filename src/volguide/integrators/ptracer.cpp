#include "volguide/integrators/ptracer.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {

// Veach's correction of the adjoint BSDF for shading normals (thesis p. 155), with Mitsuba's test that
// both directions lie on the same side of the geometric and the shading surface; 0 when they do not.
// wi_local / wo_local in the shading frame, wi_world / wo_world leaving the surface.
float ptracer_shading_correction(const SurfaceInteraction& si, const Vec3f& wi_local, const Vec3f& wi_world,
                                 const Vec3f& wo_local, const Vec3f& wo_world) {
    const float wi_geo = dot(si.n, wi_world), wo_geo = dot(si.n, wo_world);
    if (!(wi_geo * wi_local.z > 0.f && wo_geo * wo_local.z > 0.f)) return 0.f;
    return std::abs(wi_local.z * wo_geo / (wo_local.z * wi_geo));
}

}  // namespace

PtracerSettings PtracerSettings::from(const Properties& props) {
    PtracerSettings s;
    const int64_t max_depth = props.get_int("max_depth", -1);
    if (max_depth < -1)
        props.fail_at("max_depth", "max_depth must be -1 (unbounded) or >= 0, got {}", max_depth);
    const int64_t rr_depth = props.get_int("rr_depth", 5);
    if (rr_depth <= 0) props.fail_at("rr_depth", "rr_depth must be > 0, got {}", rr_depth);
    const int64_t per_pass = props.get_int("samples_per_pass", -1);
    if (per_pass == 0 || per_pass < -1)
        props.fail_at("samples_per_pass", "samples_per_pass must be > 0 (or -1: all), got {}", per_pass);
    s.max_depth = int(max_depth);
    s.rr_depth = int(rr_depth);
    s.hide_emitters = props.get_bool("hide_emitters", false);
    s.samples_per_pass = int(per_pass);
    return s;
}

std::string ParticleTracerIntegrator::to_string() const {
    return fmt::format("ptracer[max_depth={}, rr_depth={}, hide_emitters={}]", settings_.max_depth,
                       settings_.rr_depth, settings_.hide_emitters);
}

Color3 ParticleTracerIntegrator::Li(const Scene&, Sampler&, const CameraRay&) const {
    throw std::logic_error(
        "ptracer traces from the emitters and splats onto the film: it has no estimate along "
        "a camera ray (render it through the render loop)");
}

void ParticleTracerIntegrator::trace_from_emitters(const Scene& scene, Sampler& sampler,
                                                   FilmSplats& splats) const {
    if (settings_.max_depth != 0 && !settings_.hide_emitters) splat_visible_emitter(scene, sampler, splats);
    const auto [emitter, probability] = scene.sample_emitter_for_emission(sampler.next_1d());
    const Point2f u_pos = sampler.next_2d(), u_dir = sampler.next_2d();
    if (!emitter || !(probability > 0.f)) return;
    const RaySample rs = emitter->sample_ray(u_pos, u_dir);
    if (rs.weight.is_black()) return;
    trace_light_path(scene, rs.ray, rs.weight / probability, sampler, splats);
}

// One point of a non-delta emitter, drawn by the emitter's direction sampling from the sensor's
// position, splatted where the sensor sees it: importance x radiance / pdf (solid angle at the sensor).
void ParticleTracerIntegrator::splat_visible_emitter(const Scene& scene, Sampler& sampler,
                                                     FilmSplats& splats) const {
    const auto [emitter, probability] = scene.sample_emitter_for_emission(sampler.next_1d());
    const Point2f u = sampler.next_2d();
    if (!emitter || emitter->is_delta() || !(probability > 0.f)) return;
    const Sensor& sensor = scene.sensor();
    Interaction ref;
    ref.p = sensor.importance(Vec3f(0.f, 0.f, 1.f)).p;
    const auto [ds, radiance_weight] = emitter->sample_direction(ref, u);
    if (!(ds.pdf > 0.f) || radiance_weight.is_black()) return;
    SensorConnection c;
    if (emitter->is_infinite()) {
        c = sensor.importance(ds.d);
        if (c.weight > 0.f && scene.occluded(Ray(ref.p, ds.d, Infinity))) return;
    } else {
        c = sensor.connect(ds.p);
        c.weight *= c.dist * c.dist;  // per solid angle at the sensor: the emitter's pdf is
        if (c.weight > 0.f && scene.occluded(ref.spawn_ray_to(ds.p))) return;
    }
    if (c.weight > 0.f) splats.splat(c.film_pos, radiance_weight * (c.weight / probability));
}

void ParticleTracerIntegrator::trace_light_path(const Scene& scene, Ray ray, Color3 throughput,
                                                Sampler& sampler, FilmSplats& splats) const {
    const PtracerSettings& s = settings_;
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    float eta = 1.f;
    // depth = segments of the light path so far; a sensor connection adds one.
    for (int depth = 1; s.max_depth < 0 || depth < s.max_depth; ++depth) {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) return;
        const BSDF& bsdf = *si.shape->bsdf();
        connect_surface(scene, si, bsdf, throughput, splats);
        const float u1 = sampler.next_1d();
        const auto [bs, weight] = bsdf.sample(ctx, si, u1, sampler.next_2d());
        const Vec3f wo = si.to_world(bs.wo);
        throughput *= weight * ptracer_shading_correction(si, si.wi, -ray.d, bs.wo, wo);
        eta *= bs.eta;
        if (throughput.is_black()) return;
        if (depth + 1 > s.rr_depth) {
            const float q = std::min(throughput.max_value() * eta * eta, 0.95f);
            if (!(sampler.next_1d() < q)) return;
            throughput *= 1.f / q;
        }
        ray = si.spawn_ray(wo);
    }
}

void ParticleTracerIntegrator::connect_surface(const Scene& scene, const SurfaceInteraction& si,
                                               const BSDF& bsdf, const Color3& throughput,
                                               FilmSplats& splats) const {
    const SensorConnection c = scene.sensor().connect(si.p);
    if (!(c.weight > 0.f)) return;
    const Vec3f local = si.to_local(c.d);
    const float correction = ptracer_shading_correction(si, si.wi, si.to_world(si.wi), local, c.d);
    if (!(correction > 0.f)) return;
    if (scene.occluded(si.spawn_ray_to(c.p))) return;
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    const Color3 f = bsdf.eval(ctx, si, local);
    if (!f.is_black()) splats.splat(c.film_pos, throughput * f * (c.weight * correction));
}

}  // namespace volguide
