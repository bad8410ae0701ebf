#pragma once
// The volume scattering probability (VSP) distance decision in a homogeneous medium (docs/theory.md
// §7.10; the shape of Xu et al. 2024's VSPG): one decision per segment (0, s) of a ray: scatter
// inside it with probability P, else pass to its end. Inside, the distance is drawn conditioned on
// scattering from the free flight truncated to (0, s) (one-sample spectral MIS over the channels,
// §2.6: channel c picked with the throughput share q_c), so
//   p(t | scatter) = sum_c q_c sigma_c e^(-sigma_c t) / P_u,   P_u = sum_c q_c (1 - T_c(s)),
// P_u being the unguided scattering probability (free flight's). The weights are exact for any P
// with P > 0 where P_u > 0 and P < 1 where the segment transmits:
//   scatter at t:  flight weight T(t) / (P p(t | scatter)),    pass:  T(s) / (1 - P).
// With P = P_u the decision is free flight's (the same distribution and weights).
//
// Equiangular share (docs/theory.md §7.10.1, deliverable 5 of issue 37): inside the scatter branch the
// distance may come from a one-sample mixture of that truncated free flight and equiangular sampling
// on (0, s) toward a light point y drawn before t (as volpath's equiangular strategy draws it),
//   p(t | scatter, y) = (1 - e) p_ff(t | scatter) + e p_eq(t | y),
// the weights using this density. For every y it is a density on (0, s) that is positive wherever
// p_ff is (e < 1), so E[weight | y] is the segment's integral: unbiased. Homogeneous media only.
//
// Heterogeneous (and any) media: resampled_segment_flight below walks the segment's tentative
// collisions under the majorant (Medium::sample_majorant_walk) and resamples them.
#include <optional>

#include "volguide/core/color.h"
#include "volguide/core/function_ref.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/equiangular.h"
#include "volguide/media/medium.h"

namespace volguide {

class Scene;

// The equiangular part of the conditional distance: `sampler` on (0, s) toward the light point
// (null: none, free flight only) with mixture share `share` in [0, 1].
struct VspEquiangular {
    const EquiangularSampler* sampler = nullptr;
    float share = 0.f;
    bool active() const { return sampler && sampler->valid() && share > 0.f; }
};

// The equiangular sampler toward a light point for the segment (0, s) of `ray` (draws 2 numbers):
// the point chosen by scene.sample_emitter_direction from ray.o as volpath's equiangular strategy
// chooses it (equiangular_mis.h); nullopt where it cannot aim (no light, an environment or
// directional light, the point on the ray's line).
std::optional<EquiangularSampler> vsp_equiangular_toward_light(const Scene& scene, const Ray& ray, float s,
                                                               Sampler& sampler);

class HomogeneousVsp {
  public:
    // Extinction sigma_t (>= 0 per channel), segment length s (> 0, may be infinite), the
    // channel shares q (channel_probabilities of the throughput: sum 1).
    HomogeneousVsp(const Color3& sigma_t, float s, const Color3& channel_shares);

    // P_u: free flight's probability of scattering inside the segment.
    float unguided() const { return unguided_; }
    // The decision's P: the defensive mixture c P_u + (1 - c) P_G (P_G NaN: P_u); 1 where the
    // segment transmits nothing (every T_c(s) = 0), 0 where nothing can scatter (P_u = 0).
    float probability(float guided, float c) const;

    struct Sample {
        bool scattered = false;
        float t = 0.f;             // the scatter distance, or s
        Color3 flight_weight{0.f}; // T(t) / (P p(t | scatter)), or T(s) / (1 - P)
        float pdf = 0.f;           // P p(t | scatter), or 1 - P
    };
    // Decides with probability P (u_decide), then draws the channel (u_channel) and the distance (u_t).
    Sample sample(float P, float u_decide, float u_channel, float u_t) const { return sample(P, u_decide, u_channel, u_t, {}); }
    // The same with the equiangular share: u_channel first picks the strategy (equiangular below e,
    // rescaled to pick the channel otherwise); p(t | scatter) is conditional_pdf(t, equi).
    Sample sample(float P, float u_decide, float u_channel, float u_t, const VspEquiangular& equi) const;
    // p(t | scatter) on (0, s) (0 outside, and where P_u = 0).
    float conditional_pdf(float t) const;
    // (1 - e) p(t | scatter) + e p_eq(t) when equi is active, else conditional_pdf(t).
    float conditional_pdf(float t, const VspEquiangular& equi) const;

  private:
    // The free flight's distance conditioned on scattering inside (0, s).
    float truncated_free_flight(float u_channel, float u_t) const;

    Color3 sigma_t_, shares_;
    float s_;
    Color3 absorbed_;  // 1 - T_c(s) per channel
    float unguided_;
    bool opaque_;      // every T_c(s) = 0
};

// The segment decision over any medium's majorant walk (docs/theory.md §7.10): the walk visits every
// tentative collision t_i of (0, s) (rate mu_i) with ratio tracking's T^_i before it; the scatter
// candidates w_i = T^_i sigma_s(t_i) / mu_i (sum_i w_i f(t_i) is unbiased for int T sigma_s f) go
// through a one-slot reservoir by |w_i|_q (channel shares q of the throughput), the pass candidate is
// T^(s). Then: scatter at the kept candidate k with probability P, weight w_k sum_j |w_j|_q /
// (|w_k|_q P), else pass with weight T^(s) / (1 - P). P = probability(1 - |T^(s)|_q) (its argument:
// the unguided scattering probability's estimate, clamped to [0, 1]), held in [kResampledMinProbability,
// 1 - kResampledMinProbability] where both branches carry something, 0 / 1 where only one does.
// Medium::sample_free_flight's contract.
using SegmentProbability = FunctionRef<float(float)>;
constexpr float kResampledMinProbability = 0.02f;
FreeFlightSample resampled_segment_flight(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                          const SegmentProbability& probability, Sampler& sampler);

}  // namespace volguide
