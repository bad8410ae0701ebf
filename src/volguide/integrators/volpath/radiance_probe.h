#pragma once
// Brute-force radiance at a point inside a medium, by volpath's own walk started there (the
// reference the guiding field's estimates are measured against: tools/field_accuracy.cpp).
//  - incident_radiance_sample: one unbiased sample of L_i(x, w), the radiance arriving at x from the
//    direction w (towards the light, the field's convention, docs/theory.md §1.1): the walk from x
//    along w, whose first emitter hit counts fully (it is the radiance seen along w). Delta lights
//    (point, spot, directional) are never hit: their direct light is not part of it.
//  - inscattered_radiance_sample: one unbiased sample of L_s(x, d) = ∫ f_p(d, w) L_i(x, w) dw for a
//    ray travelling along d (no sigma_s): next-event estimation of the delta lights only (their direct
//    light is a delta in w), plus a phase-sampled direction w and incident_radiance_sample along it
//    (which holds every other emitter's light). No MIS is needed: the two strategies never overlap.
// Both walk with `settings` (max_depth, rr_rule, ...); volume_only and forward_first_scatter must be off.
#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/media/medium.h"

namespace volguide {

class Scene;

Color3 incident_radiance_sample(const Scene& scene, const VolPathSettings& settings, const Point3f& x,
                                const Medium* medium, const Vec3f& w, Sampler& sampler);

Color3 inscattered_radiance_sample(const Scene& scene, const VolPathSettings& settings, const Point3f& x,
                                   const Medium& medium, const Vec3f& d, Sampler& sampler);

}  // namespace volguide
