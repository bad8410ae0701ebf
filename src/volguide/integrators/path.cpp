#include "volguide/integrators/path.h"

#include <fmt/format.h>

#include "volguide/integrators/volume_nee.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

PathSettings PathSettings::from(const Properties& props) {
    PathSettings s;
    int64_t max_depth = props.get_int("max_depth", -1);
    if (max_depth < -1) props.fail_at("max_depth", "max_depth must be -1 (unbounded) or >= 0, got {}", max_depth);
    int64_t rr_depth = props.get_int("rr_depth", 5);
    if (rr_depth <= 0) props.fail_at("rr_depth", "rr_depth must be > 0, got {}", rr_depth);
    s.max_depth = int(max_depth);
    s.rr_depth = int(rr_depth);
    s.hide_emitters = props.get_bool("hide_emitters", false);
    return s;
}

std::string PathIntegrator::to_string() const {
    return fmt::format("path[max_depth={}, rr_depth={}, hide_emitters={}]", settings_.max_depth,
                       settings_.rr_depth, settings_.hide_emitters);
}

Color3 PathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    const PathSettings& s = settings_;
    if (s.max_depth == 0) return Color3(0.f);
    const BSDFContext ctx;
    Color3 result(0.f), throughput(1.f);
    float eta = 1.f;
    Ray ray = camera.ray;

    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) si = miss_interaction(ray);
    if (!s.hide_emitters)
        if (const Emitter* e = scene.emitter_seen(si)) result += e->eval(si);

    // depth = number of segments of the path so far (the camera segment is 1).
    for (int depth = 1; si.is_valid() && (s.max_depth < 0 || depth < s.max_depth); ++depth) {
        const BSDF& bsdf = *si.shape->bsdf();

        // Next-event estimation towards a sampled emitter.
        if (bsdf.has(bsdf_flags::Smooth)) {
            auto [ds, emitter_weight] = scene.sample_emitter_direction(si, sampler.next_2d(), true);
            if (ds.pdf > 0.f && !emitter_weight.is_black()) {
                Vec3f wo = si.to_local(ds.d);
                Color3 f = bsdf.eval(ctx, si, wo);
                float bsdf_pdf = bsdf.pdf(ctx, si, wo);
                float mis = ds.delta ? 1.f : mis_power_heuristic(ds.pdf, bsdf_pdf);
                result += throughput * f * emitter_weight * mis;
            }
        } else {
            sampler.next_2d();  // keep the dimension layout independent of the BSDF type
        }

        // BSDF sampling.
        float u1 = sampler.next_1d();
        Point2f u2 = sampler.next_2d();
        auto [bs, bsdf_weight] = bsdf.sample(ctx, si, u1, u2);
        throughput *= bsdf_weight;
        if (throughput.is_black()) break;
        eta *= bs.eta;

        ray = si.spawn_ray(si.to_world(bs.wo));
        SurfaceInteraction next;
        if (!scene.intersect(ray, next)) next = miss_interaction(ray);

        if (const Emitter* e = scene.emitter_seen(next)) {
            bool delta = (bs.sampled_flags & bsdf_flags::Delta) != 0;
            float emitter_pdf = 0.f;
            if (!delta) emitter_pdf = scene.pdf_emitter_direction(si, emitter_hit_record(next, si, ray.d, e));
            float mis = delta ? 1.f : mis_power_heuristic(bs.pdf, emitter_pdf);
            result += throughput * e->eval(next) * mis;
        }
        si = next;

        // Russian roulette, compensating for radiance scaling at refractive boundaries.
        if (depth + 1 > s.rr_depth) {
            float q = std::min(throughput.max_value() * eta * eta, 0.95f);
            if (!(sampler.next_1d() < q)) break;
            throughput *= 1.f / q;
        }
    }
    return result;
}

}  // namespace volguide
