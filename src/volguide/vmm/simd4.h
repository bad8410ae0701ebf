#pragma once
// Four-lane float arithmetic for the vMF kernels (vmf_sum.cpp): GCC/Clang
// vector extensions (SSE2 on x86-64, NEON on arm64; no -march needed). Internal to the kernels'
// .cpp files: the four-float loads must not be inlined into callers whose arrays GCC sees as
// shorter than four.
#include <cstring>

namespace volguide::simd4 {

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
    // Lanes flushed to 0 below compute exp(0) instead: exp(kMinNormalArg) itself can round below
    // FLT_MIN (2^-126 times a polynomial under 1), and that product takes a microcode assist in every
    // such lane (a four-lane product kernel tried for issue 20 spent a sixth of its time on it, in
    // the normalisations' e^{-2 kappa} for kappa >= 44).
    const F4 x = x_in > splat(kMinNormalArg) ? (x_in < splat(88.f) ? x_in : splat(88.f)) : splat(0.f);
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


}  // namespace volguide::simd4
