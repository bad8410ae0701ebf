#pragma once
// The scatter probability of guided null-collision tracking (docs/theory.md §7.7 H2) from a guiding
// field. At a tentative collision x with majorant mu, the zero-variance choice weighs what each
// branch would carry: scattering sigma_s L~_i(x, w), continuing (mu - sigma_t) L~(x, w) (the
// radiance arriving from further along the ray), so
//   P_G = <q sigma_s L~_i> / (<q sigma_s L~_i> + <q |mu - sigma_t| L~>),
// where <q .> sums over the channels weighted by the path's channel weights q (throughput x
// tracking weight, normalised): the zero-variance target of the throughput-weighted channel sum,
// equal to channel averages for grey light and media (docs/theory.md §7.8 uses plain averages; with
// them a chromatic medium's null weights would exceed 1 for thin channels at every collision).
// No valid leaf (outside the field, an invalid leaf, no estimates) or a non-finite P_G:
// P_G = P_a, the unguided (spectral tracking) probability.
//
// Defensive mixing with P_a (docs/theory.md §7.5), c_T = the unguided strategy's share:
//  - PerFlight (default; Variant A): the flight is a one-sample mixture of two whole trackings,
//    unguided with probability c_T and guided otherwise, with the path probability
//    c_T prod P_a + (1 - c_T) prod P_G (each product over this flight's decisions). Drawn
//    sequentially: P_s = c_k P_a + (1 - c_k) P_G with c_k the posterior probability of the unguided
//    strategy given the nulls so far (c_0 = c_T). The weight is then at most the unguided weight / c_T.
//  - PerCollision (Variant B): P_s = c_T P_a + (1 - c_T) P_G at every collision. Each factor is
//    bounded by 1 / c_T, but they compound: where the field says nothing comes from ahead (L~ ~ 0)
//    P_G ~ 1 at each of many collisions and the rare flights that pass carry weights ~ c_T^-n.
// Both keep P_s > 0 where sigma_s > 0 and P_s < 1 where mu > sigma_t whenever c_T > 0 (PerFlight:
// up to the float underflow of c_k).
//
// L~_i and L~ are read once per leaf: a tree cursor follows the ray as the collisions advance.
#include <cstdint>

#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/media/guided_tracking.h"

namespace volguide {

enum class CollisionMixture { PerFlight, PerCollision };

class GuidedCollisionProbability {
  public:
    // Guides collisions at t in (0, t_end) of `ray` (beyond: unguided). `estimates` may be null.
    // One object per flight: it infers the previous collision's outcome (a null) from the next call.
    GuidedCollisionProbability(const GuidingField& field, const LeafEstimates* estimates, const Ray& ray,
                               float t_end, float c_T,
                               CollisionMixture mixture = CollisionMixture::PerFlight);

    // P_s at the tentative collision c (called in order of increasing t; media/majorant_tracking.h's
    // guided_tracking takes it as its scatter probability).
    float scatter_probability(const TentativeCollision& c);
    float operator()(const TentativeCollision& c) { return scatter_probability(c); }

    // Counters of this query.
    uint64_t collisions() const { return collisions_; }
    uint64_t unguided_collisions() const { return unguided_; }  // no valid leaf: P_s = P_a
    uint64_t nan_fallbacks() const { return nan_fallbacks_; }   // P_G not finite: P_s = P_a

  private:
    // Moves the cursor to the leaf containing ray(t) (t never decreases); false if there is none.
    bool enter_leaf_at(float t);

    const GuidingField& field_;
    const LeafEstimates* estimates_;
    LeafEstimates::Direction direction_;  // the ray's place in the leaves' tables (computed once)
    CollisionMixture mixture_;
    float unguided_share_;         // c_k: the unguided strategy's share at the current collision
    bool has_previous_ = false;  // the previous collision's probabilities (it was a null)
    float previous_unguided_ = 0.f, previous_guided_ = 0.f;
    SpatialTree::RayCursor cursor_;
    bool cursor_done_ = false;
    float leaf_t0_ = 0.f, leaf_t1_ = 0.f;  // the current leaf's interval (empty before the first)
    bool leaf_valid_ = false;
    Color3 inscattered_{0.f}, L_{0.f};
    uint64_t collisions_ = 0, unguided_ = 0, nan_fallbacks_ = 0;
};

}  // namespace volguide
