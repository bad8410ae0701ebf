#include "volguide/guiding/guided_collision.h"

#include <cmath>

namespace volguide {

GuidedCollisionProbability::GuidedCollisionProbability(const GuidingField& field,
                                                       const LeafEstimates* estimates, const Ray& ray,
                                                       float t_end, float c_T, CollisionMixture mixture)
    : field_(field),
      estimates_(estimates),
      direction_(estimates ? estimates->prepare(ray.d) : LeafEstimates::Direction{}),
      mixture_(mixture),
      unguided_share_(c_T),
      cursor_(field.tree(), ray, 0.f, t_end) {}

bool GuidedCollisionProbability::enter_leaf_at(float t) {
    while (!(t < leaf_t1_)) {
        int leaf;
        if (cursor_done_ || !cursor_.next(leaf, leaf_t0_, leaf_t1_)) {
            cursor_done_ = true;
            return false;
        }
        leaf_valid_ = estimates_ && estimates_->lookup(leaf, direction_, inscattered_, L_);
    }
    return t >= leaf_t0_;  // before the field's entry point there is no leaf
}

float GuidedCollisionProbability::scatter_probability(const TentativeCollision& c) {
    ++collisions_;
    if (has_previous_ && mixture_ == CollisionMixture::PerFlight) {
        // Bayes: the previous collision was a null under both strategies' probabilities.
        const float unguided = unguided_share_ * (1.f - previous_unguided_);
        const float total = unguided + (1.f - unguided_share_) * (1.f - previous_guided_);
        if (total > 0.f) unguided_share_ = unguided / total;
    }
    const float p_unguided = unguided_scatter_probability(c);
    float p_guided = p_unguided;
    if (!enter_leaf_at(c.t) || !leaf_valid_) {
        ++unguided_;
    } else {
        float scatter = 0.f, null = 0.f;
        for (int ch = 0; ch < 3; ++ch) {
            const float q = c.channel_weights[ch];
            scatter += q * std::abs(c.sigma_s[ch]) * inscattered_[ch];
            null += q * std::abs(c.mu - c.sigma_t[ch]) * L_[ch];
        }
        // No scattering (or no light from it): 0; nothing carried by a null (null = 0): 1.
        const float p = scatter > 0.f ? scatter / (scatter + null) : 0.f;
        if (std::isfinite(p) && std::isfinite(scatter + null))
            p_guided = p;
        else
            ++nan_fallbacks_;
    }
    has_previous_ = true;
    previous_unguided_ = p_unguided;
    previous_guided_ = p_guided;
    return unguided_share_ * p_unguided + (1.f - unguided_share_) * p_guided;
}

}  // namespace volguide
