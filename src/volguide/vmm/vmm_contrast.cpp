#include "volguide/vmm/vmm_contrast.h"

#include <algorithm>
#include <cmath>

namespace volguide {

double directional_contrast(const Vmm& vmm) {
    if (vmm.size() == 0) return 0.0;
    // ∫ V^2 = sum_ij w_i w_j ∫ v_i v_j, each term the exact convolution of two lobes at their angle.
    double integral = 0.0;
    for (int i = 0; i < vmm.size(); ++i)
        for (int j = 0; j < vmm.size(); ++j) {
            const VmfLobe a = vmm.lobe(i), b = vmm.lobe(j);
            integral += double(vmm.weight[i]) * vmm.weight[j] *
                        vmf_convolution_exact(a.kappa, b.kappa, one_minus_cos(a.mu, b.mu));
        }
    return std::max(0.0, 4.0 * M_PI * integral - 1.0);
}

}  // namespace volguide
