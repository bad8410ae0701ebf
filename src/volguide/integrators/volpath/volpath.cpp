// Volumetric path tracer (Mitsuba 3's volpath semantics, see volpath.h): settings and the entry
// points; the walk itself is volpath_walk.h.
#include "volguide/integrators/volpath/volpath.h"

#include <fmt/format.h>

#include <algorithm>

#include "volguide/core/log.h"
#include "volguide/integrators/path.h"
#include "volguide/integrators/volpath/volpath_walk.h"
#include "volguide/media/medium.h"
#include "volguide/render/scene.h"

namespace volguide {

float roulette_survival(RouletteRule rule, float beta_max_eta2) {
    // Mitsuba caps the survival at 0.95 so that every path ends eventually, at the price of weights
    // growing by 1/0.95 per event while beta stays near 1. The bounded rule does not cap: a path of
    // weight >= 1 always continues, and the absorption (albedo < 1) or leaving the medium ends it.
    const float cap = rule == RouletteRule::Mitsuba ? 0.95f : 1.f;
    return std::min(beta_max_eta2, cap);
}

const char* roulette_rule_name(RouletteRule rule) { return rule == RouletteRule::Mitsuba ? "mitsuba" : "bounded"; }

namespace {

RouletteRule read_roulette_rule(const Properties& props) {
    const std::string name = props.get_string("rr_rule", "mitsuba");
    if (name == "mitsuba") return RouletteRule::Mitsuba;
    if (name == "bounded") return RouletteRule::Bounded;
    props.fail_at("rr_rule", "volpath: invalid rr_rule '{}' (one of: mitsuba, bounded)", name);
}

}  // namespace

VolPathSettings VolPathSettings::from(const Properties& props) {
    VolPathSettings s;
    const PathSettings path = PathSettings::from(props);  // max_depth, rr_depth, hide_emitters
    s.max_depth = path.max_depth;
    s.rr_depth = path.rr_depth;
    s.hide_emitters = path.hide_emitters;
    s.equiangular = props.get_bool("equiangular", false);
    s.volume_only = props.get_bool("volume_only", false);
    s.forward_first_scatter = props.get_bool("forward_first_scatter", false);
    s.rr_rule = read_roulette_rule(props);
    if (s.forward_first_scatter && s.equiangular)
        props.fail_at("forward_first_scatter", "volpath: forward_first_scatter cannot be combined with equiangular");
    return s;
}

std::string VolPathIntegrator::to_string() const {
    return fmt::format(
        "volpath[max_depth={}, rr_depth={}, hide_emitters={}, equiangular={}, volume_only={}, "
        "forward_first_scatter={}, rr_rule={}]",
        settings_.max_depth, settings_.rr_depth, settings_.hide_emitters, settings_.equiangular, settings_.volume_only,
        settings_.forward_first_scatter, roulette_rule_name(settings_.rr_rule));
}

void VolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext&) {
    work_.clear();
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
    return walk(scene, sampler, camera.ray, nullptr, nullptr, &work_.local());
}

Color3 VolPathIntegrator::walk(const Scene& scene, Sampler& sampler, const Ray& ray, WalkPolicy* policy,
                               PathRecorder* recorder, WorkCounts* work) const {
    VolumeWalk w(scene, settings_, sampler, policy, recorder);
    const Color3 L = w.run(ray);
    if (work) *work += w.work();
    return L;
}

WorkCounts VolPathIntegrator::total_work() const {
    WorkCounts total;
    for (const WorkCounts& w : work_) total += w;
    return total;
}

std::vector<std::pair<std::string, double>> named_work(const WorkCounts& work) {
    std::vector<std::pair<std::string, double>> out;
    for (size_t k = 0; k < kWorkUnits; ++k) out.emplace_back(std::string("work_") + kWorkNames[k], double(work.n[k]));
    return out;
}

}  // namespace volguide
