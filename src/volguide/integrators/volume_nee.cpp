#include "volguide/integrators/volume_nee.h"

#include <cmath>

#include "volguide/media/medium.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {
// A shadow ray crossing more null surfaces than this is treated as blocked (it can only happen
// when a ray keeps re-hitting the surface it starts on).
constexpr int MaxNullCrossings = 256;
}  // namespace

Color3 shadow_transmittance(const Scene& scene, const Interaction& ref, const Medium* medium,
                            const DirectionSample& ds, Sampler& sampler) {
    const bool infinite = std::isinf(ds.dist);
    Ray ray = infinite ? ref.spawn_ray(ds.d) : ref.spawn_ray_to(ds.p);
    Color3 tr(1.f);
    for (int crossing = 0; crossing <= MaxNullCrossings; ++crossing) {
        SurfaceInteraction si;
        const bool hit = scene.intersect(ray, si);
        if (medium) {
            tr *= medium->transmittance(ray, hit ? si.t : ray.tmax, sampler);
            if (tr.is_black()) return tr;
        }
        if (!hit) return tr;
        tr *= si.shape->bsdf()->eval_null_transmission(si);
        if (tr.is_black()) return tr;
        medium = medium_after(si, ray.d, medium);
        ray = infinite ? si.spawn_ray(ray.d) : si.spawn_ray_to(ds.p);
        if (!(ray.tmax > 0.f)) return tr;
    }
    return Color3(0.f);
}

VolumeEmitterSample sample_emitter_through_media(const Scene& scene, const Interaction& ref,
                                                 const SurfaceInteraction* ref_surface, const Medium* medium,
                                                 Point2f u, Sampler& sampler) {
    VolumeEmitterSample es;
    auto [ds, weight] = scene.sample_emitter_direction(ref, u, false);
    es.ds = ds;
    if (!(ds.pdf > 0.f) || weight.is_black()) return es;
    if (ref_surface) medium = medium_after(*ref_surface, ds.d, medium);
    es.weight = weight * shadow_transmittance(scene, ref, medium, ds, sampler);
    return es;
}

DirectionSample emitter_hit_record(const SurfaceInteraction& si, const Interaction& ref, const Vec3f& ray_d,
                                   const Emitter* emitter) {
    DirectionSample ds;
    ds.emitter = emitter;
    if (!si.is_valid()) {
        ds.d = ray_d;
        ds.dist = Infinity;
        return ds;
    }
    ds.p = si.p;
    ds.n = si.sh_frame.n;
    ds.uv = si.uv;
    Vec3f d = si.p - ref.p;
    ds.dist = norm(d);
    ds.d = ds.dist > 0.f ? d / ds.dist : ray_d;
    return ds;
}

}  // namespace volguide
