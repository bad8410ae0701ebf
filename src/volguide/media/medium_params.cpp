#include "volguide/media/medium_params.h"

#include "volguide/media/phase_isotropic.h"

namespace volguide {

MediumParams read_medium_params(const Properties& props) {
    MediumParams mp;
    mp.sigma_t = volume_param(props, "sigma_t", Color3(1.f));
    mp.albedo = volume_param(props, "albedo", Color3(0.75f));
    mp.scale = props.get_float("scale", 1.f);
    mp.sample_emitters = props.get_bool("sample_emitters", true);
    if (!std::isfinite(mp.scale) || mp.scale < 0.f)
        props.fail_at("scale", "{}: scale must be finite and non-negative (got {})", props.type(), mp.scale);
    if (!(mp.sigma_t->min_value() >= 0.f) || !std::isfinite(mp.sigma_t->max_value()))
        props.fail_at("sigma_t", "{}: sigma_t must be finite and non-negative (min {})", props.type(),
                      mp.sigma_t->min_value());
    if (!(mp.albedo->min_value() >= 0.f) || !(mp.albedo->max_value() <= 1.f))
        props.fail_at("albedo", "{}: the albedo must lie in [0, 1] (range [{}, {}])", props.type(),
                      mp.albedo->min_value(), mp.albedo->max_value());

    auto phases = props.children("phase");
    if (phases.size() > 1)
        fail(phases[1]->loc, "{}: a medium takes at most one phase function", props.type());
    if (phases.empty()) {
        mp.phase = std::make_shared<IsotropicPhase>();
    } else {
        mp.phase = std::dynamic_pointer_cast<PhaseFunction>(std::get<ObjectPtr>(phases[0]->value));
        if (!mp.phase) fail(phases[0]->loc, "{}: the <phase> child is not a phase function", props.type());
    }
    return mp;
}

}  // namespace volguide
