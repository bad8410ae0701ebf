#pragma once
// Adaptive lobe count for the batch EM (the idea of openpgl-notes §1.4 with simpler criteria; see
// docs/vmm.md): split a lobe when two lobes explain its samples significantly better (BIC), merge
// two lobes when one moment-matched lobe represents them almost exactly (closed-form L2).
#include <span>

#include "volguide/vmm/vmm_fit.h"

namespace volguide {

// For every lobe, refits the samples it is responsible for (weights x responsibility) with two
// lobes; splits when the log-likelihood gain exceeds split_threshold x the BIC penalty of the four
// extra parameters, 2 ln(evidence). Returns the number of splits (bounded by the capacity).
int split_lobes(Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings);

// Relative squared L2 distance between a_w v_a + b_w v_b and their moment-matched merge, in closed
// form from vMF product integrals.
double merge_cost(const WeightedLobe& a, const WeightedLobe& b);

// Greedily merges the cheapest pair while its cost is below settings.merge_threshold and more than
// settings.min_lobes remain. Returns the number of merges.
int merge_redundant_lobes(Vmm& vmm, const VmmFitSettings& settings);

}  // namespace volguide
