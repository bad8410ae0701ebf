#include "volguide/integrators/direct.h"

#include <fmt/format.h>

#include "volguide/integrators/volume_nee.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {

int read_count(const Properties& props, const char* name, int64_t def) {
    const int64_t n = props.get_int(name, def);
    if (n < 0 || n > (1 << 20)) props.fail_at(name, "direct: {} must be in [0, 2^20], got {}", name, n);
    return int(n);
}


}  // namespace

DirectSettings DirectSettings::from(const Properties& props) {
    DirectSettings s;
    const int shading = read_count(props, "shading_samples", 1);
    s.emitter_samples = read_count(props, "emitter_samples", shading);
    s.bsdf_samples = read_count(props, "bsdf_samples", shading);
    if (s.emitter_samples + s.bsdf_samples == 0)
        props.fail_here("direct: emitter_samples and bsdf_samples are both 0 (nothing would be sampled)");
    s.hide_emitters = props.get_bool("hide_emitters", false);
    return s;
}

std::string DirectIntegrator::to_string() const {
    return fmt::format("direct[emitter_samples={}, bsdf_samples={}, hide_emitters={}]", settings_.emitter_samples,
                       settings_.bsdf_samples, settings_.hide_emitters);
}

float DirectIntegrator::emitter_share() const {
    return float(settings_.emitter_samples) / float(settings_.emitter_samples + settings_.bsdf_samples);
}

Color3 DirectIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    SurfaceInteraction si;
    if (!scene.intersect(camera.ray, si)) si = miss_interaction(camera.ray);
    Color3 result(0.f);
    if (!settings_.hide_emitters)
        if (const Emitter* e = scene.emitter_seen(si)) result += e->eval(si);
    if (!si.is_valid()) return result;
    result += emitter_sampling(scene, sampler, si);
    result += bsdf_sampling(scene, sampler, si);
    return result;
}

Color3 DirectIntegrator::emitter_sampling(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si) const {
    const BSDF& bsdf = *si.shape->bsdf();
    // Mitsuba samples emitters only for BSDFs with a non-delta lobe.
    if (!bsdf.has(bsdf_flags::Smooth)) return Color3(0.f);
    const BSDFContext ctx;
    Color3 sum(0.f);
    for (int i = 0; i < settings_.emitter_samples; ++i) {
        auto [ds, emitter_weight] = scene.sample_emitter_direction(si, sampler.next_2d(), true);
        if (!(ds.pdf > 0.f) || emitter_weight.is_black()) continue;
        const Vec3f wo = si.to_local(ds.d);
        const float bsdf_pdf = bsdf.pdf(ctx, si, wo);
        const float mis = ds.delta ? 1.f : mis_power_heuristic(ds.pdf * emitter_share(), bsdf_pdf * bsdf_share());
        sum += bsdf.eval(ctx, si, wo) * emitter_weight * mis;
    }
    return sum / float(std::max(settings_.emitter_samples, 1));
}

Color3 DirectIntegrator::bsdf_sampling(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si) const {
    const BSDF& bsdf = *si.shape->bsdf();
    const BSDFContext ctx;
    Color3 sum(0.f);
    for (int i = 0; i < settings_.bsdf_samples; ++i) {
        const float u1 = sampler.next_1d();
        const Point2f u2 = sampler.next_2d();
        auto [bs, bsdf_weight] = bsdf.sample(ctx, si, u1, u2);
        if (bsdf_weight.is_black()) continue;
        const Ray ray = si.spawn_ray(si.to_world(bs.wo));
        SurfaceInteraction next;
        if (!scene.intersect(ray, next)) next = miss_interaction(ray);
        const Emitter* e = scene.emitter_seen(next);
        if (!e) continue;
        const bool delta = (bs.sampled_flags & bsdf_flags::Delta) != 0;
        const float emitter_pdf =
            delta || settings_.emitter_samples == 0
                ? 0.f
                : scene.pdf_emitter_direction(si, emitter_hit_record(next, si, ray.d, e));
        const float mis = delta ? 1.f : mis_power_heuristic(bs.pdf * bsdf_share(), emitter_pdf * emitter_share());
        sum += bsdf_weight * e->eval(next) * mis;
    }
    return sum / float(std::max(settings_.bsdf_samples, 1));
}

}  // namespace volguide
