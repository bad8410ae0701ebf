#include "volguide/integrators/guided/walk/walk_guide.h"

namespace volguide {

namespace {

PreparedFieldSettings prepared_settings(const WalkGuideSettings& s) {
    return {s.distance != DistanceGuiding::Standard, s.estimate_table, s.distance_merge};
}

TrustSettings trust_settings(const WalkGuideSettings& s) {
    return {s.distance_settings.c_T, s.phase_prob, s.bsdf_prob, s.leaf_tau_max};
}

DistanceSettings distance_settings(const WalkGuideSettings& s) {
    return {s.distance_settings, s.max_bin_optical_depth, s.leaf_tau_max, s.vsp_equiangular};
}

}  // namespace

WalkGuide::WalkGuide(const Scene& scene, const GuidingField& field, const WalkGuideSettings& settings)
    : scene_(scene),
      settings_(settings),
      prepared_(scene, field, prepared_settings(settings)),
      trust_(prepared_.leaf_extents(), trust_settings(settings)),
      distance_(make_distance_sampler(settings.distance, distance_settings(settings), scene)),
      free_flight_(make_distance_sampler(DistanceGuiding::Standard, distance_settings(settings), scene)) {}

WalkGuide::~WalkGuide() = default;

std::array<float, kDecisionKinds> WalkGuide::configured_shares() const {
    return {trust_.configured_share(DecisionKind::Distance), trust_.configured_share(DecisionKind::Direction),
            trust_.configured_share(DecisionKind::Surface)};
}

}  // namespace volguide
