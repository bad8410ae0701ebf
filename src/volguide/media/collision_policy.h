#pragma once
// The decision at a tentative collision of a null-collision walk (docs/theory.md §2.2, §7.7 H2): the
// medium walks the collisions at its majorant rate mu; a policy chooses at each one whether the
// flight scatters there or continues, and with which probability. The walk owns the weights:
//   scatter:   flight weight = w * factor,                       factor = 1 / (mu P_s)
//   continue:  w <- w * (mu - sigma_t(x)) * factor,               factor = 1 / (mu (1 - P_s))
// (absorption folded into the weight; the walk then multiplies sigma_s in at the scatter).
// A policy is a class with
//   static constexpr bool reads_scattering;   // needs sigma_s before deciding (else only at a scatter)
//   CollisionDecision operator()(const TentativeCollision&, Sampler&);
// passed as a template argument so that the unguided decision inlines into the walk (media/
// majorant_tracking.h's track_collisions); a guided walk pays one indirect call per collision, the
// medium's majorant walk handing the collision to the caller.
#include <algorithm>
#include <cmath>

#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/media/guided_tracking.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

struct CollisionDecision {
    enum class Event { Scatter, Null, Vanish } event;  // Vanish: nothing can be carried further (weight 0)
    float factor = 0.f;  // the weight's factor of the chosen event (see above)
};

// Spectral tracking (Kutz et al. 2017; guided_tracking.h's spectral_tracking_weights):
// P_s = real / (real + null), drawn with the channel averages pc = real / 3, pn = null / 3 of the
// walk's unnormalised channel weights. For grey sigma_t: delta tracking with weight = albedo. The
// factors are written as z / (mu P) with z = pc + pn (no division by z first).
struct SpectralTrackingPolicy {
    static constexpr bool reads_scattering = false;
    CollisionDecision operator()(const TentativeCollision& c, Sampler& sampler) const {
        const SpectralTrackingWeights s = spectral_tracking_weights(c);
        const float pc = s.real * (1.f / 3.f), pn = s.null * (1.f / 3.f);
        const float z = pc + pn;
        if (!(z > 0.f)) return {CollisionDecision::Event::Vanish};  // the tracking weight vanished
        if (sampler.next_1d() * z < pc) return {CollisionDecision::Event::Scatter, z / (c.mu * pc)};
        return {CollisionDecision::Event::Null, z / (c.mu * pn)};
    }
};

// Guided null-collision tracking: P_s from the caller's scatter probability (a callable
// float(const TentativeCollision&)), which sees the channel weights normalised (NaN: the unguided
// probability; clamped to [0, 1]).
template <class ScatterProbability>
struct GuidedTrackingPolicy {
    static constexpr bool reads_scattering = true;
    ScatterProbability& probability;
    CollisionDecision operator()(const TentativeCollision& c, Sampler& sampler) const {
        TentativeCollision seen = c;
        seen.channel_weights = channel_probabilities(c.channel_weights);
        float ps = probability(seen);
        ps = std::isnan(ps) ? unguided_scatter_probability(seen) : std::clamp(ps, 0.f, 1.f);
        // u in [0, 1): P_s = 0 never scatters and P_s = 1 always does, so each factor's division
        // is by a probability of at least ~1e-7 (weights stay finite).
        if (sampler.next_1d() < ps) return {CollisionDecision::Event::Scatter, 1.f / (c.mu * ps)};
        return {CollisionDecision::Event::Null, 1.f / (c.mu * (1.f - ps))};
    }
};

}  // namespace volguide
