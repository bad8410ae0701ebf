#include "volguide/vmm/vmm_variance_aware.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/math.h"

namespace volguide {

double vmf_effective_solid_angle(double kappa) {
    // tanh(k) / k -> 1 - k^2 / 3 below the uniform threshold.
    if (kappa < double(kVmfUniformKappa)) return 4.0 * Pi;
    return 4.0 * Pi * std::tanh(kappa) / kappa;
}

bool variance_aware_weights(Vmm& vmm, std::span<const DirectionalSample> second_moments,
                            const VmmFitSettings& settings) {
    // The E-step's per-lobe statistic sum_i u_i gamma_ik is M2_k up to one factor for all lobes
    // (the weights' normalisation), which the normalisation below removes.
    VmmStatistics stats;
    expectation(vmm, second_moments, settings, stats);
    if (!(stats.total > 0.0)) return false;
    double s[kVmmMaxLobes] = {};
    double sum = 0.0;
    for (int k = 0; k < vmm.count; ++k) {
        s[k] = std::sqrt(vmf_effective_solid_angle(vmm.kappa[k]) * std::max(stats.weight[k], 0.0));
        sum += s[k];
    }
    if (!(sum > 0.0) || !std::isfinite(sum)) return false;
    for (int k = 0; k < vmm.count; ++k) vmm.weight[k] = float(s[k] / sum);
    return true;
}

}  // namespace volguide
