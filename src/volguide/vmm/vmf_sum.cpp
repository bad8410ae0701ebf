#include "volguide/vmm/vmf_sum.h"

#include <cstring>

namespace volguide {

namespace {

using F4 = float __attribute__((vector_size(16)));
using I4 = int __attribute__((vector_size(16)));

F4 load(const float* p) {
    F4 v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}
F4 splat(float x) { return F4{x, x, x, x}; }

// exp(x) for each lane; NaN stays NaN, x < -104 gives 0 and x > 88 gives e^88 (no caller passes
// positive arguments: they are -kappa (1 - cos) <= 0).
F4 exp4(F4 x_in) {
    const F4 x = x_in > splat(-104.f) ? (x_in < splat(88.f) ? x_in : splat(88.f)) : splat(-104.f);
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
    // 2^n in two factors, so that n down to -150 (denormal results) needs no special case.
    const I4 n1 = n >> 1, n2 = n - n1;
    const F4 s1 = (F4)((n1 + 127) << 23), s2 = (F4)((n2 + 127) << 23);
    const F4 e = p * s1 * s2;
    return x_in == x_in ? e : x_in;
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
