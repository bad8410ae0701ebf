#include "volguide/integrators/openpgl/openpgl_settings.h"

#include <fmt/format.h>

#include "volguide/integrators/openpgl/openpgl_version.h"

namespace volguide {

namespace {

float probability(const Properties& props, const char* name, float def) {
    const float v = props.get_float(name, def);
    if (!(v >= 0.f && v <= 1.f)) props.fail_at(name, "openpgl_volpath: {} must be in [0, 1], got {}", name, v);
    return v;
}

// vsp=true needs the 0.8 API: with any other Open PGL it is an error naming the linked version.
bool read_vsp(const Properties& props) {
    const bool vsp = props.get_bool("vsp", false);
    if (vsp && !kOpenPglHasVsp)
        props.fail_at("vsp",
                      "openpgl_volpath: vsp=true needs Open PGL 0.8 with volume scattering probability guiding, "
                      "but this build links Open PGL {} (configure with -DVOLGUIDE_OPENPGL_SOURCE=0.8)",
                      kOpenPglVersion);
    return vsp;
}

}  // namespace

OpenPglSettings OpenPglSettings::from(const Properties& props) {
    OpenPglSettings s;
    s.walk = VolPathSettings::from(props);
    // The recorder attributes every contribution to the path's vertices; equiangular sampling adds
    // a third direct-light strategy it does not know.
    if (s.walk.equiangular)
        props.fail_at("equiangular", "openpgl_volpath: equiangular sampling is not supported");
    if (s.walk.forward_first_scatter || s.walk.volume_only)
        props.fail_here("openpgl_volpath: forward_first_scatter and volume_only are volpath's inspection modes");
    s.phase_prob = probability(props, "phase_prob", s.phase_prob);
    s.bsdf_prob = probability(props, "bsdf_prob", s.bsdf_prob);
    s.volume_guiding = props.get_bool("volume_guiding", s.volume_guiding);
    s.surface_guiding = props.get_bool("surface_guiding", s.surface_guiding);
    const int64_t spp = props.get_int("training_spp", s.training_spp);
    if (spp < 0 || spp > (1 << 20))
        props.fail_at("training_spp", "openpgl_volpath: training_spp must be in [0, 2^20], got {}", spp);
    s.training_spp = int(spp);
    s.training_fraction = props.get_float("training_fraction", s.training_fraction);
    if (!(s.training_fraction > 0.f && s.training_fraction <= 1.f))
        props.fail_at("training_fraction", "openpgl_volpath: training_fraction must be in (0, 1], got {}",
                      s.training_fraction);
    const int64_t leaf = props.get_int("max_samples_per_leaf", s.max_samples_per_leaf);
    if (leaf < 100 || leaf > (1 << 24))
        props.fail_at("max_samples_per_leaf", "openpgl_volpath: max_samples_per_leaf must be in [100, 2^24], got {}",
                      leaf);
    s.max_samples_per_leaf = int(leaf);
    s.vsp = read_vsp(props);
    // c > 0 keeps P > 0 wherever free flight can scatter and P < 1 wherever the segment transmits,
    // whatever Open PGL's VSP says: the weights stay bounded and the estimator unbiased.
    s.vsp_unguided_prob = props.get_float("vsp_unguided_prob", s.vsp_unguided_prob);
    if (!(s.vsp_unguided_prob > 0.f && s.vsp_unguided_prob <= 1.f))
        props.fail_at("vsp_unguided_prob", "openpgl_volpath: vsp_unguided_prob must be in (0, 1], got {}",
                      s.vsp_unguided_prob);
    s.location = props.location();
    return s;
}

std::string OpenPglSettings::to_string() const {
    return fmt::format(
        "max_depth={}, rr_depth={}, hide_emitters={}, phase_prob={}, bsdf_prob={}, volume_guiding={}, "
        "surface_guiding={}, training_spp={}, training_fraction={}, max_samples_per_leaf={}, vsp={}, "
        "vsp_unguided_prob={}",
        walk.max_depth, walk.rr_depth, walk.hide_emitters, phase_prob, bsdf_prob, volume_guiding, surface_guiding,
        training_spp, training_fraction, max_samples_per_leaf, vsp, vsp_unguided_prob);
}

}  // namespace volguide
