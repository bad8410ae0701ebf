#pragma once
// The variance-aware target of Rath et al. 2020 on a fitted mixture (docs/theory.md §23): the lobes
// (axes, concentrations) stay those of the radiance fit; the lobe weights are refitted so that the
// mixture follows sqrt(E[L^2]), from samples of the second moment L^2 / p.
#include <span>

#include "volguide/vmm/vmm_fit.h"

namespace volguide {

struct VarianceAwareSettings {
    int max_iterations = 64;
    double tolerance = 1e-4;  // stop when no lobe's s_k changes by more than this, relatively
};

// Samples are (direction, second moment m = L^2 / p). With g = sum_k s_k v_k (the mixture's lobes,
// s_k >= 0), minimises F(s) = 1/2 int g^2 - int m log g (convex; its minimum over all functions is
// g = sqrt(m)) by the multiplicative update s_k <- sqrt(s_k M_k / (G s)_k), where
// M_k = sum_i gamma_ik m_i with responsibilities gamma_ik = s_k v_k(w_i) / g(w_i) and
// G_kj = int v_k v_j (eq. 3.3), from the mixture's own weights (theory §23.2). The weights become
// s / sum(s). Returns false and leaves the mixture unchanged when no sample carries a positive second
// moment the mixture explains (the caller keeps the radiance weights).
bool variance_aware_weights(Vmm& vmm, std::span<const DirectionalSample> second_moments,
                            const VmmFitSettings& fit = {}, const VarianceAwareSettings& settings = {});

}  // namespace volguide
