#include "volguide/vmm/vmm_variance_aware.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace volguide {

namespace {

using LobeValues = std::array<double, kVmmMaxLobes>;

// G s with G_kj = int v_k v_j, the scale of the lobes' product (eq. 3.3).
LobeValues gram_times(const Vmm& vmm, const LobeValues& s) {
    LobeValues out{};
    for (int k = 0; k < vmm.count; ++k)
        for (int j = 0; j < vmm.count; ++j) out[k] += vmf_product(vmm.lobe(k), vmm.lobe(j)).scale * s[j];
    return out;
}

// One multiplicative update of s (the mixture's weights are s / sum(s) on entry); returns the
// largest relative change, or -1 when the samples carry nothing the mixture explains.
double variance_aware_step(Vmm& vmm, LobeValues& s, std::span<const DirectionalSample> samples,
                           const VmmFitSettings& fit) {
    // The E-step's per-lobe statistic sum_i u_i gamma_ik is M_k times one factor for all lobes
    // (the weights' normalisation): it scales s by its square root, which the final
    // normalisation removes.
    VmmStatistics stats;
    expectation(vmm, samples, fit, stats);
    if (!(stats.total > 0.0)) return -1.0;
    const LobeValues gs = gram_times(vmm, s);
    double change = 0.0, sum = 0.0;
    for (int k = 0; k < vmm.count; ++k) {
        const double next = gs[k] > 0.0 ? std::sqrt(s[k] * std::max(stats.weight[k], 0.0) / gs[k]) : 0.0;
        if (s[k] > 0.0) change = std::max(change, std::abs(next - s[k]) / s[k]);
        s[k] = next;
        sum += next;
    }
    if (!(sum > 0.0) || !std::isfinite(sum)) return -1.0;
    for (int k = 0; k < vmm.count; ++k) vmm.weight[k] = float(s[k] / sum);
    return change;
}

}  // namespace

bool variance_aware_weights(Vmm& vmm, std::span<const DirectionalSample> second_moments, const VmmFitSettings& fit,
                            const VarianceAwareSettings& settings) {
    if (vmm.count == 0) return false;
    Vmm work = vmm;
    LobeValues s{};
    for (int k = 0; k < vmm.count; ++k) s[k] = vmm.weight[k];
    for (int i = 0; i < settings.max_iterations; ++i) {
        const double change = variance_aware_step(work, s, second_moments, fit);
        if (change < 0.0) return false;
        if (change < settings.tolerance) break;
    }
    vmm = work;
    return true;
}

}  // namespace volguide
