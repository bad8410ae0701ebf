#pragma once
// The decision at a tentative collision of a null-collision walk (theory.md §2.2, §7.7 H2): the
// medium walks the collisions at its majorant rate mu; a policy chooses at each one whether the
// flight scatters there or continues, and with which probability. The walk owns the weights:
//   scatter:   flight weight = w * factor,                       factor = 1 / (mu P_s)
//   continue:  w <- w * (mu - sigma_t(x)) * factor,               factor = 1 / (mu (1 - P_s))
// (absorption folded into the weight; the walk then multiplies sigma_s in at the scatter).
// A policy is a class with
//   static constexpr bool reads_scattering;   // needs sigma_s before deciding (else only at a scatter)
//   CollisionDecision operator()(const CollisionSite&, Sampler&);
// passed as a template argument so that the analog decision inlines into the walk; a guided walk
// pays one virtual call per collision, inside its CollisionGuide.
#include <algorithm>
#include <cmath>

#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/media/guided_tracking.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

// What a policy sees at a tentative collision.
struct CollisionSite {
    float t;              // ray parameter
    float mu;             // the majorant cell's rate
    Color3 sigma_t;       // at ray(t)
    Color3 sigma_s;       // at ray(t) if the policy reads_scattering, else unset
    Color3 path_weight;   // channel probabilities on entry x the tracking weight so far (not normalised)
};

struct CollisionDecision {
    enum class Event { Scatter, Null, Vanish } event;  // Vanish: nothing can be carried further (weight 0)
    float factor = 0.f;  // the weight's factor of the chosen event (see above)
};

// Spectral tracking (Kutz et al. 2017): P_s = <|sigma_t q|> / (<|sigma_t q|> + <|sigma_n q|>),
// sigma_n = mu - sigma_t, q the path weight (<.> = channel average); with absolute values it stays
// unbiased where mu < sigma_t. For grey sigma_t: delta tracking with weight = albedo. The factors
// are written as z / (mu P) with z = the sum of the two averages (no division by z first).
struct SpectralTrackingPolicy {
    static constexpr bool reads_scattering = false;
    CollisionDecision operator()(const CollisionSite& c, Sampler& sampler) const {
        const Color3 sigma_n = Color3(c.mu) - c.sigma_t;
        const float pc = abs(c.sigma_t * c.path_weight).average(), pn = abs(sigma_n * c.path_weight).average();
        const float z = pc + pn;
        if (!(z > 0.f)) return {CollisionDecision::Event::Vanish};  // the tracking weight vanished
        if (sampler.next_1d() * z < pc) return {CollisionDecision::Event::Scatter, z / (c.mu * pc)};
        return {CollisionDecision::Event::Null, z / (c.mu * pn)};
    }

private:
    static Color3 abs(const Color3& c) { return {std::abs(c.r), std::abs(c.g), std::abs(c.b)}; }
};

// Guided null-collision tracking: P_s from the caller's CollisionGuide (NaN: the analog
// probability; clamped to [0, 1]).
struct GuidedTrackingPolicy {
    static constexpr bool reads_scattering = true;
    CollisionGuide& guide;
    CollisionDecision operator()(const CollisionSite& s, Sampler& sampler) const {
        const TentativeCollision c{s.t, s.mu, s.sigma_t, s.sigma_s, channel_probabilities(s.path_weight)};
        float ps = guide.scatter_probability(c);
        ps = std::isnan(ps) ? analog_scatter_probability(c) : std::clamp(ps, 0.f, 1.f);
        // u in [0, 1): P_s = 0 never scatters and P_s = 1 always does, so each factor's division
        // is by a probability of at least ~1e-7 (weights stay finite).
        if (sampler.next_1d() < ps) return {CollisionDecision::Event::Scatter, 1.f / (s.mu * ps)};
        return {CollisionDecision::Event::Null, 1.f / (s.mu * (1.f - ps))};
    }
};

}  // namespace volguide
