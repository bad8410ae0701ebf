#include "volguide/vmm/vmf_sum.h"

#include <cstring>

namespace volguide {

namespace {

using F4 = float __attribute__((vector_size(16)));
using I4 = int __attribute__((vector_size(16)));

[[gnu::always_inline]] inline F4 load(const float* p) {
    F4 v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}
[[gnu::always_inline]] inline F4 splat(float x) { return F4{x, x, x, x}; }

// exp(x) for each lane; NaN stays NaN, x > 88 gives e^88 (no caller passes positive arguments:
// they are -kappa (1 - cos) <= 0) and results below FLT_MIN (x < -87.34) are 0. Flushing matters:
// strongly peaked lobes put most terms there, and every float operation with a denormal operand or
// result takes a microcode assist (it made this kernel slower than glibc's expf in aniso's profile);
// a denormal term is below 1e-38 of its lobe's scale, nothing a probability can see.
[[gnu::always_inline]] inline F4 exp4(F4 x_in) {
    constexpr float kMinNormalArg = -87.33654475f;  // ln(FLT_MIN)
    const F4 x = x_in > splat(kMinNormalArg) ? (x_in < splat(88.f) ? x_in : splat(88.f)) : splat(kMinNormalArg);
    // n = round(x / ln 2), r = x - n ln 2 (Cody-Waite, two parts) in [-ln2 / 2, ln2 / 2].
    const F4 fx = x * splat(1.44269504088896341f);
    const I4 n = __builtin_convertvector(fx + (fx < splat(0.f) ? splat(-0.5f) : splat(0.5f)), I4);
    const F4 fn = __builtin_convertvector(n, F4);
    const F4 r = (x - fn * splat(0.693359375f)) - fn * splat(-2.12194440e-4f);
    // Cephes expf's minimax polynomial: e^r = 1 + r + r^2 P(r).
    F4 p = splat(1.9875691500e-4f);
    p = p * r + splat(1.3981999507e-3f);
    p = p * r + splat(8.3334519073e-3f);
    p = p * r + splat(4.1665795894e-2f);
    p = p * r + splat(1.6666665459e-1f);
    p = p * r + splat(5.0000001201e-1f);
    p = p * (r * r) + r + splat(1.f);
    // 2^n, n in [-126, 127], built in the exponent bits.
    const F4 e = p * (F4)((n + 127) << 23);
    const F4 flushed = x_in > splat(kMinNormalArg) ? e : splat(0.f);  // the bound itself rounds below FLT_MIN
    return x_in == x_in ? flushed : x_in;
}

}  // namespace

float vmf_exp(float x) { return exp4(splat(x))[0]; }

float vmf_sum(const float* mu_x, const float* mu_y, const float* mu_z, const float* kappa,
                     const float* weight, const float* norm, int count, const Vec3f& w) {
    const F4 wx = splat(w.x), wy = splat(w.y), wz = splat(w.z);
    F4 acc = splat(0.f);
    auto terms = [&](F4 mx, F4 my, F4 mz, F4 k, F4 scale) {
        const F4 dx = wx - mx, dy = wy - my, dz = wz - mz;
        F4 omc = splat(0.5f) * (dx * dx + dy * dy + dz * dz);
        omc = omc < splat(2.f) ? omc : splat(2.f);
        return scale * exp4(-k * omc);
    };
    int i = 0;
    for (; i + 4 <= count; i += 4) {
        const F4 scale = weight ? load(weight + i) * load(norm + i) : load(norm + i);
        acc += terms(load(mu_x + i), load(mu_y + i), load(mu_z + i), load(kappa + i), scale);
    }
    if (i < count) {  // the last 1-3 lobes in zero-padded lanes (scale 0 adds exactly 0)
        float t[5][4] = {};
        for (int j = 0; i + j < count; ++j) {
            t[0][j] = mu_x[i + j], t[1][j] = mu_y[i + j], t[2][j] = mu_z[i + j], t[3][j] = kappa[i + j];
            t[4][j] = weight ? weight[i + j] * norm[i + j] : norm[i + j];
        }
        acc += terms(load(t[0]), load(t[1]), load(t[2]), load(t[3]), load(t[4]));
    }
    return (acc[0] + acc[1]) + (acc[2] + acc[3]);
}

}  // namespace volguide
