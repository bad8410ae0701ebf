#include "volguide/integrators/simple_volpath.h"

#include <fmt/format.h>

#include "volguide/integrators/path.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/media/medium.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

SimpleVolPathIntegrator::SimpleVolPathIntegrator(const Properties& props) {
    const PathSettings s = PathSettings::from(props);
    max_depth_ = s.max_depth;
    rr_depth_ = s.rr_depth;
    hide_emitters_ = s.hide_emitters;
}

std::string SimpleVolPathIntegrator::to_string() const {
    return fmt::format("simple_volpath[max_depth={}, rr_depth={}, hide_emitters={}]", max_depth_, rr_depth_,
                       hide_emitters_);
}

Color3 SimpleVolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    const BSDFContext ctx;
    Color3 result(0.f), throughput(1.f);
    Ray ray = camera.ray;
    const Medium* medium = scene.sensor().medium();
    int depth = 0;  // real scattering events
    int null_crossings = 0;
    while (true) {
        if (max_depth_ >= 0 && depth >= max_depth_) break;
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) si = miss_interaction(ray);
        if (medium) {
            FreeFlightSample ff = medium->sample_free_flight(ray, si.is_valid() ? si.t : ray.tmax, throughput, sampler);
            throughput *= ff.weight;
            if (throughput.is_black()) break;
            if (ff.scattered) {
                ++depth;
                const Medium& m = ff.mi.medium ? *ff.mi.medium : *medium;
                PhaseSample ps = m.phase().sample(ff.mi.wi, sampler.next_2d());
                if (!(ps.pdf > 0.f)) break;
                throughput *= ps.weight;
                ray = ff.mi.spawn_ray(ps.wo);
                if (depth > rr_depth_) {
                    const float q = std::min(throughput.max_value(), 0.95f);
                    if (!(sampler.next_1d() < q)) break;
                    throughput *= 1.f / q;
                }
                continue;
            }
        }
        const Emitter* emitter = scene.emitter_seen(si);
        if (emitter && !(depth == 0 && hide_emitters_)) result += throughput * emitter->eval(si);
        if (!si.is_valid()) break;

        const BSDF& bsdf = *si.shape->bsdf();
        const float u1 = sampler.next_1d();
        auto [bs, weight] = bsdf.sample(ctx, si, u1, sampler.next_2d());
        throughput *= weight;
        if (throughput.is_black()) break;
        const Vec3f wo = si.to_world(bs.wo);
        medium = medium_after(si, wo, medium);
        ray = si.spawn_ray(wo);
        if (bs.sampled_flags & bsdf_flags::Null) {
            if (++null_crossings > kMaxNullCrossings) break;
        } else {
            ++depth;
            if (depth > rr_depth_) {
                const float q = std::min(throughput.max_value(), 0.95f);
                if (!(sampler.next_1d() < q)) break;
                throughput *= 1.f / q;
            }
        }
    }
    return result;
}

}  // namespace volguide
