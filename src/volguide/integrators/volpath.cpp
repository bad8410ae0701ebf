// Volumetric path tracer (Mitsuba 3's volpath semantics, see volpath.h): settings and the entry
// points; the walk itself is volpath_walk.h.
#include "volguide/integrators/volpath.h"

#include <fmt/format.h>

#include "volguide/core/log.h"
#include "volguide/integrators/path.h"
#include "volguide/integrators/volpath_walk.h"
#include "volguide/media/medium.h"
#include "volguide/render/scene.h"

namespace volguide {

VolPathSettings VolPathSettings::from(const Properties& props) {
    VolPathSettings s;
    const PathSettings path = PathSettings::from(props);  // max_depth, rr_depth, hide_emitters
    s.max_depth = path.max_depth;
    s.rr_depth = path.rr_depth;
    s.hide_emitters = path.hide_emitters;
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

Color3 VolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    return walk(scene, sampler, camera.ray, nullptr);
}

Color3 VolPathIntegrator::walk(const Scene& scene, Sampler& sampler, const Ray& ray, WalkPolicy* policy) const {
    return VolumeWalk(scene, settings_, sampler, policy).run(ray);
}

}  // namespace volguide
