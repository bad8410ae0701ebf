#pragma once
// sum_i weight_i norm_i exp(-kappa_i (1 - mu_i . w)) over lobes stored as a structure of arrays, four
// lobes at a time: VmfMixture::eval and the InscatterCache, i.e. the render-time guiding queries (L~
// and L~_i per distance bin, the guided direction pdf), where glibc's scalar expf, one call per lobe,
// was the largest single cost (bench_vmm BM_VmmEval8, bench_guiding).
//
// The exponential is a Cephes-style polynomial within 2 ulp of expf down to FLT_MIN, and 0 below
// (denormal terms cost a microcode assist per operation; test_vmf_sum), so sums differ from
// one-lobe-at-a-time sums by float rounding only. Mixture values only shape probabilities, and a sampler's decisions and its pdf read the same
// values, so weights stay exact (docs/theory.md §1.4).
//
// Plain C++ with GCC/Clang vector extensions (SSE2 on x86-64, NEON on arm64: no -march needed), out of
// line in vmf_sum.cpp: the four-float loads must not be inlined into callers whose arrays GCC sees
// as shorter than four (it warns, although count keeps them in bounds).
#include "volguide/core/vec.h"

namespace volguide {

// exp(x) with the lanes' arithmetic, for one value (tests): within 2 ulp of std::exp where that is at
// least FLT_MIN, 0 below (x < -87.34); NaN stays NaN.
float vmf_exp(float x);

// sum_i weight_i norm_i exp(-kappa_i min(|w - mu_i|^2 / 2, 2)); `weight` may be null (all ones).
// Reads exactly `count` entries of each array. The order of the additions is fixed by `count`.
float vmf_sum(const float* mu_x, const float* mu_y, const float* mu_z, const float* kappa, const float* weight,
              const float* norm, int count, const Vec3f& w);

}  // namespace volguide
