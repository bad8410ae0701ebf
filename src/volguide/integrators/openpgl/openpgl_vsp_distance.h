#pragma once
// The distance decision of openpgl_volpath with vsp=true (the VSPG peer row, issue 37): one decision
// per segment (0, tmax) of a ray leaving a guided vertex, with the scatter probability
//   P = c P_u + (1 - c) VSP
// where VSP is Open PGL 0.8's volume scattering probability of the vertex's guiding distribution in
// the sampled direction (openpgl_version.h), P_u free flight's probability of scattering in the
// segment and c = vsp_unguided_prob (> 0: P > 0 wherever free flight scatters, P < 1 wherever the
// segment transmits). Inside the segment the distance is drawn conditioned on scattering; the weights
// are the exact ratios of docs/theory.md §7.10, so the estimator is unbiased whatever Open PGL
// returns. This is the shape Xu et al. 2024 give and vspg-pbrt-v4 / Cycles use; the samplers are
// volguide's own (integrators/guided/walk/vsp_distance.h: the truncated exponential with spectral
// MIS in homogeneous media, resampling of the majorant walk's tentative collisions in any other), so
// the peer row differs from distance="vsp" in where P comes from, not in how it is applied.
#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/media/medium.h"

namespace volguide {

// The decision for `query`: vsp in [0, 1] (the caller falls back to free flight where Open PGL gives
// none); c in (0, 1].
FreeFlightSample openpgl_vsp_flight(const DistanceQuery& query, float vsp, float c, Sampler& sampler);

}  // namespace volguide
