#pragma once
// The parameters of `openpgl_volpath` (docs/scene-format.md), read and checked once from the
// scene's <integrator> properties. Defaults are Blender Cycles' for its Open PGL guiding.
#include <string>

#include "volguide/core/error.h"
#include "volguide/core/properties.h"
#include "volguide/integrators/volpath/volpath.h"

namespace volguide {

struct OpenPglSettings {
    VolPathSettings walk;  // max_depth, rr_depth, hide_emitters (equiangular is rejected)
    // Probability of the medium's phase function (resp. the BSDF) in the one-sample mixture with
    // Open PGL's guided distribution at a guided vertex (Cycles: 1 - volume/surface guiding
    // probability = 0.5). 1 disables guiding there.
    float phase_prob = 0.5f;
    float bsdf_prob = 0.5f;
    bool volume_guiding = true;
    bool surface_guiding = true;
    // Training: the first passes of the render record their camera paths and update the field after
    // each pass, until training_spp samples per pixel (Cycles' default 128 training samples) or,
    // under --time, until the end of the first pass past training_fraction of the budget. Their
    // samples count toward the image, as in Cycles.
    int training_spp = 128;
    float training_fraction = 0.25f;
    int max_samples_per_leaf = 32000;  // Open PGL's kd-tree split threshold (its default)
    // Open PGL's volume scattering probability guiding (VSPG; needs Open PGL 0.8 with
    // OPENPGL_EF_VSP_GUIDING, openpgl_version.h): the distance decision of a segment leaving a guided
    // vertex takes its scatter probability from the guiding distribution's VSP in the sampled direction,
    // mixed defensively with free flight's (openpgl_vsp_distance.h). false: free flight everywhere.
    bool vsp = false;
    // The free-flight share c of that mixture: P = c P_u + (1 - c) VSP.
    float vsp_unguided_prob = 0.5f;
    SourceLocation location;

    static OpenPglSettings from(const Properties& props);
    std::string to_string() const;
};

}  // namespace volguide
