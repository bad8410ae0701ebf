#pragma once
// How much a guided decision trusts the guiding field at a point: the one rule every decision of the
// guided walk reads (TrustRule::guided_share, WalkGuide::trust()), and the leaf confidence it is built on.
//
// A leaf many mean free paths across holds one estimate for radiance that varies on the scale of a
// free path (deep in a dense medium it is near-isotropic while the leaf's VMM carries the light at its
// boundary); following it at every one of hundreds of events compounds its error into the path
// weights. So a decision's guided share is scaled by the confidence of the leaf around the point,
// toward the unguided decision (free flight, the phase function, the BSDF), and below
// kSkipConfidence the decision is made unguided outright. Only probabilities are shaped: every
// decision's weight is its mixture's exact density, whatever the share.
#include <cstdint>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

// The guiding confidence of a leaf (or leaf group) of `extent` (the cube root of its volume) in a
// medium of extinction sigma_t: min(1, tau_max / tau_leaf), tau_leaf = extent x sigma_t's channel
// average; 1 when tau_max is 0 (off). WalkGuideSettings::leaf_tau_max sets tau_max.
inline float leaf_confidence(float extent, const Color3& sigma_t, float tau_max) {
    if (!(tau_max > 0.f)) return 1.f;
    const float tau = extent * sigma_t.average();
    return tau > tau_max ? tau_max / tau : 1.f;
}

// Below this confidence a decision at a medium vertex follows no guide: the direction product is not
// built and the guided bins are not walked (the guided share would be under a quarter, and the guided
// work costs more than it can return): phase sampling and free flight.
inline constexpr float kSkipConfidence = 0.25f;

// The point a decision is made at, as the trust rule reads it.
struct TrustPoint {
    DecisionKind kind = DecisionKind::Distance;
    // The guiding leaf whose confidence applies (-1: none, confidence 1: a point outside the field,
    // or a decision whose point has no leaf estimate to damp, as the camera segment's pixel buffer).
    int leaf = -1;
    // The extinction at the point (read only when leaf >= 0).
    Color3 sigma_t{0.f};
    // The allocation's share of the point's cell (Allocation::kConfigured: none learned, or the
    // decision explores; the configured share applies).
    float learned = -1.f;
    // A medium vertex of the walk: below kSkipConfidence the decision is unguided. False: a distance
    // decision leaving a surface or the camera, which is damped by the confidence but never skipped.
    bool vertex = true;
};

// Why a decision's guided share is what it is (the counters read it).
enum class ShareSource : uint8_t {
    Configured,  // the configuration's share (1 - c_T, 1 - phase_prob, 1 - bsdf_prob)
    Learned,     // the allocation's share of the cell (> 0)
    Unselected,  // the allocation's share of the cell is 0: the unguided decision
    Skipped,     // a medium vertex in a leaf of confidence < kSkipConfidence: the unguided decision
};

struct GuidedShare {
    // s: the probability that the decision follows the guide (its mixture's unguided part is 1 - s),
    // the configured or learned share times the leaf's confidence; 0 when Unselected or Skipped.
    float share = 0.f;
    // The configured or learned share before the confidence. The distance decision over bins
    // (incremental) damps each bin by its own leaf's confidence instead and reads this.
    float undamped = 0.f;
    float confidence = 1.f;  // the leaf's (1: no leaf)
    ShareSource source = ShareSource::Configured;
    bool guided() const { return source == ShareSource::Configured || source == ShareSource::Learned; }
};

// The configured shares and the confidence's tau_max (WalkGuideSettings' values).
struct TrustSettings {
    float c_T = 0.5f;         // the distance decision's unguided share (GuidedDistanceSettings::c_T)
    float phase_prob = 0.5f;  // the direction decision's (alpha_f)
    float bsdf_prob = 0.5f;   // the surface decision's
    float leaf_tau_max = 1.f;
};

// The rule: a decision's guided share from its point (the leaf's confidence and the learned share).
class TrustRule {
  public:
    // `leaf_extent` (per leaf, the cube root of its volume) must outlive the rule.
    TrustRule(const std::vector<float>& leaf_extent, const TrustSettings& settings)
        : leaf_extent_(leaf_extent), settings_(settings) {}

    // The confidence of `leaf` at extinction sigma_t (leaf_confidence); 1 for -1.
    float confidence(int leaf, const Color3& sigma_t) const {
        if (leaf < 0) return 1.f;
        return leaf_confidence(leaf_extent_[size_t(leaf)], sigma_t, settings_.leaf_tau_max);
    }
    // The guided share of the decision at `point`, the one rule for how much a decision follows the
    // guide: s = s_0 x the confidence of point.leaf at point.sigma_t, s_0 the learned share
    // point.learned where one was learned, else the configured one (1 - c_T, 1 - phase_prob,
    // 1 - bsdf_prob for the distance, direction and surface decisions); s = 0 where the learned share
    // is 0 (Unselected) and at a medium vertex whose leaf's confidence is below kSkipConfidence
    // (Skipped). The distance family keeps its mixture as the unguided share c_T (GuidedDistanceSettings),
    // so its s_0 is 1 - c_T with c_T = 1 - the learned share. Every decision's mixture takes 1 - s (the
    // incremental distance decision 1 - undamped, its bins damped by their own leaves).
    GuidedShare guided_share(const TrustPoint& point) const;
    // Whether the field's estimate at `leaf` may be read at extinction sigma_t (the continuation's
    // estimate): a leaf whose confidence is at least kSkipConfidence.
    bool trusted(int leaf, const Color3& sigma_t) const {
        return leaf >= 0 && confidence(leaf, sigma_t) >= kSkipConfidence;
    }
    // The guided share the configuration sets for decisions of `kind` (what the pilot samples with):
    // 1 - c_T, 1 - phase_prob, 1 - bsdf_prob.
    float configured_share(DecisionKind kind) const {
        switch (kind) {
            case DecisionKind::Distance: return 1.f - settings_.c_T;
            case DecisionKind::Direction: return 1.f - settings_.phase_prob;
            case DecisionKind::Surface: break;
        }
        return 1.f - settings_.bsdf_prob;
    }
    float leaf_tau_max() const { return settings_.leaf_tau_max; }

  private:
    const std::vector<float>& leaf_extent_;
    TrustSettings settings_;
};

}  // namespace volguide
