#include "volguide/integrators/volpath/radiance_probe.h"

#include "volguide/integrators/volpath/volpath_walk.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/render/scene.h"

namespace volguide {

Color3 incident_radiance_sample(const Scene& scene, const VolPathSettings& settings, const Point3f& x,
                                const Medium* medium, const Vec3f& w, Sampler& sampler) {
    return VolumeWalk(scene, settings, sampler, nullptr).run_from(Ray(x, w), medium);
}

Color3 inscattered_radiance_sample(const Scene& scene, const VolPathSettings& settings, const Point3f& x,
                                   const Medium& medium, const Vec3f& d, Sampler& sampler) {
    MediumInteraction mi;
    mi.p = x;
    mi.n = Normal3f(0.f);
    mi.t = 0.f;
    mi.wi = -d;
    mi.medium = &medium;
    mi.coeffs = medium.eval(x);
    const PhaseFunction& phase = medium.phase();
    Color3 result(0.f);
    // The delta lights' direct light (the walk along a sampled direction never hits them).
    if (medium.sample_emitters()) {
        const VolumeEmitterSample es = sample_emitter_through_media(scene, mi, nullptr, &medium, sampler.next_2d(), sampler);
        if (es.ds.delta && !es.weight.is_black()) result += es.weight * phase.eval(mi.wi, es.ds.d);
    }
    // Everything else: a direction from the phase function (weight f_p / p), then the radiance from it.
    const PhaseSample ps = phase.sample(mi.wi, sampler.next_2d());
    if (ps.pdf > 0.f && ps.weight > 0.f)
        result += ps.weight * incident_radiance_sample(scene, settings, x, &medium, ps.wo, sampler);
    return result;
}

}  // namespace volguide
