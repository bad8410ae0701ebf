#pragma once
// Henyey-Greenstein phase function as a zonal vMF mixture (docs/theory.md §4.3-4.4), looked up in the
// generated table with linear interpolation of (weight, A3(kappa)) between neighbouring entries.
//
// Convention (docs/theory.md §1.1): with w the travel direction, f_HG(w, w') is centred on w for g > 0,
// so the lobes have sign +1 (axis w) for g > 0 and -1 (axis -w) for g < 0. g = 0 gives one uniform
// lobe. |g| beyond the table (0.99) uses the last entry: the mixture only shapes probabilities,
// weights always use the true HG (docs/theory.md §4.4).
#include "volguide/vmm/phase_vmm_table.h"
#include "volguide/vmm/vmm.h"

namespace volguide {

using PhaseVmm = ZonalMixture<kPhaseVmmMaxLobes>;

PhaseVmm hg_phase_vmm(float g);

// Sum_j w_j A3(kappa_j) sign_j: the mean cosine of the mixture (HG's is g).
float mean_cosine(const PhaseVmm& phase);

}  // namespace volguide
