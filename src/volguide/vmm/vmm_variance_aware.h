#pragma once
// The variance-aware target of Rath et al. 2020 on a fitted mixture (docs/theory.md §23): the lobes
// (axes, concentrations) stay those of the radiance fit; the lobe weights become proportional to each
// lobe's share of sqrt(E[L^2]), estimated from samples of the second moment L^2 / p.
#include <span>

#include "volguide/vmm/vmm_fit.h"

namespace volguide {

// 1 / integral of v^2 over the sphere = 4 pi tanh(kappa) / kappa (4 pi for the uniform lobe): the
// solid angle over which a function shaped like the lobe has the lobe's L2 norm (theory §23.2).
double vmf_effective_solid_angle(double kappa);

// Samples are (direction, second moment L^2 / p); responsibilities are the mixture's own. Per lobe
// k, M2_k = sum_i gamma_ik m_i and the new weight is sqrt(A_k M2_k), normalised (A_k the effective
// solid angle). Returns false and leaves the mixture unchanged when no sample carries a positive
// second moment the mixture explains (the caller keeps the radiance weights).
bool variance_aware_weights(Vmm& vmm, std::span<const DirectionalSample> second_moments,
                            const VmmFitSettings& settings = {});

}  // namespace volguide
