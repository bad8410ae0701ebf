#include "volguide/vmm/vmm_product_simd.h"

#include <cmath>

#include "volguide/core/math.h"
#include "volguide/vmm/simd4.h"
#include "volguide/vmm/vmf.h"

namespace volguide {

using namespace simd4;

namespace {

// -expm1(x) for x in [-0.5, 0]: Taylor to x^8 (the next term is below 1.2e-8 of the result).
[[gnu::always_inline]] inline F4 minus_expm1_small(F4 x) {
    F4 p = splat(1.f) + x * splat(1.f / 8.f);
    p = splat(1.f) + x * splat(1.f / 7.f) * p;
    p = splat(1.f) + x * splat(1.f / 6.f) * p;
    p = splat(1.f) + x * splat(1.f / 5.f) * p;
    p = splat(1.f) + x * splat(1.f / 4.f) * p;
    p = splat(1.f) + x * splat(1.f / 3.f) * p;
    p = splat(1.f) + x * splat(1.f / 2.f) * p;
    return -(x * p);
}

// c~(kappa) per lane, vmf_normalization_fast's branches: the series below 1e-3, kappa / 2 pi from 9
// on, kappa / (2 pi (1 - e^{-2 kappa})) between (with expm1 below 0.25, where 1 - e^{-2 kappa} cancels).
[[gnu::always_inline]] inline F4 normalization4(F4 kappa) {
    const F4 series = (splat(1.f) + kappa + kappa * kappa * splat(1.f / 3.f)) * splat(InvFourPi);
    const F4 large = kappa * splat(InvTwoPi);
    const F4 x = splat(-2.f) * kappa;
    const F4 denom = kappa >= splat(0.25f) ? splat(1.f) - exp4(x) : minus_expm1_small(x);
    const F4 mid = kappa * splat(InvTwoPi) / denom;  // 0 / 0 in lanes of kappa 0: not selected
    return kappa < splat(1e-3f) ? series : (kappa >= splat(9.f) ? large : mid);
}

// Four lanes of a's arrays from `k` (zero past `count`: scale 0, left out of the maximum).
struct Lanes {
    F4 weight, mu_x, mu_y, mu_z, kappa, norm;
};
Lanes lanes(const VmfLobeArrays& a, int k) {
    if (k + 4 <= a.count)
        return {load(a.weight + k), load(a.mu_x + k), load(a.mu_y + k), load(a.mu_z + k), load(a.kappa + k),
                load(a.norm + k)};
    float t[6][4] = {};
    for (int i = 0; k + i < a.count; ++i) {
        t[0][i] = a.weight[k + i], t[1][i] = a.mu_x[k + i], t[2][i] = a.mu_y[k + i];
        t[3][i] = a.mu_z[k + i], t[4][i] = a.kappa[k + i], t[5][i] = a.norm[k + i];
    }
    return {load(t[0]), load(t[1]), load(t[2]), load(t[3]), load(t[4]), load(t[5])};
}

}  // namespace

float product_lobes_simd(const VmfLobeArrays& a, const VmfLobeArrays& b, const VmfLobeOutput& out, float* exponent) {
    F4 max_exponent = splat(-INFINITY);
    const int n = a.count;
    for (int j = 0; j < b.count; ++j) {
        const F4 kb = splat(b.kappa[j]), bx = splat(b.mu_x[j]), by = splat(b.mu_y[j]), bz = splat(b.mu_z[j]);
        const F4 b_scale = splat(b.norm[j]), b_weight = splat(b.weight[j]);
        for (int k = 0; k < n; k += 4) {
            const Lanes la = lanes(a, k);
            // 1 - cos from the difference (no cancellation near cos = 1), as one_minus_cos_fast.
            const F4 dx = la.mu_x - bx, dy = la.mu_y - by, dz = la.mu_z - bz;
            F4 omc = splat(0.5f) * (dx * dx + dy * dy + dz * dz);
            omc = omc < splat(2.f) ? omc : splat(2.f);
            const F4 ka = la.kappa;
            const F4 k12 = sqrt4((ka - kb) * (ka - kb) + splat(2.f) * ka * kb * (splat(2.f) - omc));
            const F4 denom = k12 + ka + kb;
            const F4 e = denom > splat(0.f) ? splat(-2.f) * ka * kb * omc / denom : splat(0.f);
            const F4 mx = ka * la.mu_x + kb * bx, my = ka * la.mu_y + kb * by, mz = ka * la.mu_z + kb * bz;
            const F4 m_norm = sqrt4(mx * mx + my * my + mz * mz);
            const auto uniform = (k12 < splat(kVmfUniformKappa)) | !(m_norm > splat(0.f));
            const F4 kappa12 = uniform ? splat(0.f) : k12;
            const F4 norm12 = normalization4(kappa12);
            const F4 inv = splat(1.f) / m_norm;
            const F4 ox = uniform ? la.mu_x : mx * inv, oy = uniform ? la.mu_y : my * inv,
                     oz = uniform ? la.mu_z : mz * inv;
            const F4 weight = la.weight * (la.norm * b_scale / norm12) * b_weight;
            // Padded lanes have weight 0: left out of the maximum like massless lobes.
            max_exponent = weight > splat(0.f) ? (e > max_exponent ? e : max_exponent) : max_exponent;
            const int slot = j * n + k;
            if (k + 4 <= n) {
                std::memcpy(out.weight + slot, &weight, sizeof(F4));
                std::memcpy(out.mu_x + slot, &ox, sizeof(F4));
                std::memcpy(out.mu_y + slot, &oy, sizeof(F4));
                std::memcpy(out.mu_z + slot, &oz, sizeof(F4));
                std::memcpy(out.kappa + slot, &kappa12, sizeof(F4));
                std::memcpy(out.norm + slot, &norm12, sizeof(F4));
                std::memcpy(exponent + slot, &e, sizeof(F4));
            } else {
                for (int i = 0; k + i < n; ++i) {
                    out.weight[slot + i] = weight[i];
                    out.mu_x[slot + i] = ox[i];
                    out.mu_y[slot + i] = oy[i];
                    out.mu_z[slot + i] = oz[i];
                    out.kappa[slot + i] = kappa12[i];
                    out.norm[slot + i] = norm12[i];
                    exponent[slot + i] = e[i];
                }
            }
        }
    }
    return std::fmax(std::fmax(max_exponent[0], max_exponent[1]), std::fmax(max_exponent[2], max_exponent[3]));
}

float scale_by_exponent_simd(float* weight, const float* exponent, int n, float max_exponent) {
    F4 sum = splat(0.f);
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        const F4 w = load(weight + i) * exp4(load(exponent + i) - splat(max_exponent));
        std::memcpy(weight + i, &w, sizeof(w));
        sum += w;
    }
    float tail = 0.f;
    for (; i < n; ++i) {
        weight[i] *= exp4(splat(exponent[i] - max_exponent))[0];
        tail += weight[i];
    }
    return ((sum[0] + sum[1]) + (sum[2] + sum[3])) + tail;
}

void vmf_normalization_simd(const float kappa[4], float out[4]) {
    const F4 n = normalization4(load(kappa));
    std::memcpy(out, &n, sizeof(n));
}

}  // namespace volguide
