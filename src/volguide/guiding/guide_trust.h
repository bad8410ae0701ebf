#pragma once
// The one fallback rule of the guided decisions (issue 56, item 4): how far a vertex may trust its
// leaf, from what the leaf itself knows, so that the decision falls back to volpath's by itself where
// the field cannot predict or has nothing to predict.
//
// Its two factors are what tools/field_accuracy measured (bench/RESULTS.md, issue 56):
//  - optical size: the leaf holds one fluence; across a leaf of optical size tau (sigma_t x the cube
//    root of its volume) the true fluence varies by about e^(tau / l), l its e-folding length in mean
//    free paths, so an optically large leaf at a medium's boundary misses the local fluence. Factor
//    min(1, tau_max / tau): the rule leaf_tau_max already applies (distance_bins.h: leaf_confidence).
//  - directional contrast: chi2 = 4 pi ∫ V(w)^2 dw - 1, the chi-square divergence of the leaf's
//    normalised VMM from the uniform density — the relative variance of the radiance over directions,
//    i.e. the most a direction decision can gain over an isotropic one. Where the light is nearly
//    isotropic (deep in a diffusive medium) the guide's shape is right but there is nothing to gain.
//    Factor clamp((chi2 - c) / c, 0, 1): no trust below c, full trust from 2c.
// Pure: no scene, no field; inputs are the leaf's statistics. Not yet wired into the decisions: measured
// harmless where guiding wins but not enough to fix a dense back-lit medium (bench/RESULTS.md, issue 56).
#include "volguide/vmm/vmm.h"

namespace volguide {

struct GuideTrustSettings {
    float tau_max = 1.f;         // optical size up to which a leaf is fully trusted (0: no size factor)
    float contrast_min = 0.5f;   // chi2 below which the leaf has nothing to guide (0: no contrast factor)
};

// chi2 = 4 pi ∫ V^2 dw - 1 >= 0 of a normalised mixture (0 for the uniform density, and for an empty one).
double directional_contrast(const Vmm& vmm);

// The trust in [0, 1] a decision's guided share is multiplied by at a leaf of optical size
// `optical_size` (sigma_t's channel average x the cube root of the leaf's volume) whose VMM of the
// light the decision guides by has contrast `contrast` (directional_contrast).
float guide_trust(float optical_size, double contrast, const GuideTrustSettings& settings = {});

}  // namespace volguide
