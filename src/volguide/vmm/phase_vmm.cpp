#include "volguide/vmm/phase_vmm.h"

#include <cmath>

namespace volguide {

PhaseVmm hg_phase_vmm(float g) {
    PhaseVmm out;
    const float abs_g = std::abs(g);
    if (!(abs_g > 0.f)) {  // g = 0 (or NaN): isotropic
        out.count = 1;
        out.weight[0] = 1.f;
        out.kappa[0] = 0.f;
        out.sign[0] = 1.f;
        return out;
    }
    const PhaseVmmTable& table = kHgPhaseVmmTable;
    const int last = kPhaseVmmTableEntries - 1;
    float x = std::min(abs_g / table.max_g, 1.f) * float(last);
    int i = std::min(int(x), last - 1);
    float t = x - float(i);
    const PhaseVmmTableEntry &a = table.entries[i], &b = table.entries[i + 1];
    const float sign = g > 0.f ? 1.f : -1.f;
    float weight_sum = 0.f;
    out.count = table.lobes;
    for (int j = 0; j < table.lobes; ++j) {
        float w = lerp(t, a.weight[j], b.weight[j]);
        float r = lerp(t, a.mean_cosine[j], b.mean_cosine[j]);
        out.weight[j] = w;
        out.kappa[j] = float(vmf_kappa_from_mean_cosine(r, 1e6));
        out.sign[j] = sign;
        weight_sum += w;
    }
    for (int j = 0; j < out.count; ++j) out.weight[j] /= weight_sum;
    return out;
}

float mean_cosine(const PhaseVmm& phase) {
    double m = 0.0;
    for (int j = 0; j < phase.count; ++j)
        m += double(phase.weight[j]) * phase.sign[j] * vmf_mean_cosine(phase.kappa[j]);
    return float(m);
}

}  // namespace volguide
