// Highway's per-target compilation: foreach_target.h includes this file once per target, each time
// with HWY_NAMESPACE naming that target; the dispatch tables and wrappers are compiled once (HWY_ONCE).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volguide/vmm/vmf_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "volguide/vmm/vmf_simd.h"

HWY_BEFORE_NAMESPACE();
namespace volguide {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most kLobeLanes lanes: a block is padded to 8, so wider vectors (AVX-512) would only add pad lanes.
using Tag = hn::CappedTag<float, kLobeLanes>;
using V = hn::Vec<Tag>;
// Exponent of lanes without mass: below any real one, e^(it - anything) = 0, and finite for Exp.
constexpr float kNoMass = -3e38f;

// 1 - mu . a and 1 + mu . a of unit mu and a from |mu -+ a|^2 / 2 (no cancellation near +-1).
HWY_INLINE void cos_pair(Tag d, V mx, V my, V mz, const Vec3f& a, V& one_minus, V& one_plus) {
    const V ax = hn::Set(d, a.x), ay = hn::Set(d, a.y), az = hn::Set(d, a.z), half = hn::Set(d, 0.5f);
    const V two = hn::Set(d, 2.f);
    const V dx = hn::Sub(mx, ax), dy = hn::Sub(my, ay), dz = hn::Sub(mz, az);
    const V sx = hn::Add(mx, ax), sy = hn::Add(my, ay), sz = hn::Add(mz, az);
    one_minus = hn::Min(hn::Mul(half, hn::MulAdd(dx, dx, hn::MulAdd(dy, dy, hn::Mul(dz, dz)))), two);
    one_plus = hn::Min(hn::Mul(half, hn::MulAdd(sx, sx, hn::MulAdd(sy, sy, hn::Mul(sz, sz)))), two);
}

// sum_k scale_k e^(-kappa_k (1 - mu_k . w) - shift); `max_exponent` receives the largest exponent
// among the lanes with mass.
float block_sum(const LobeBlock& b, const Vec3f& w, float shift, float& max_exponent) {
    const Tag d;
    const size_t n = hn::Lanes(d);
    V sum = hn::Zero(d), vmax = hn::Set(d, kNoMass);
    const V zero = hn::Zero(d), no_mass = hn::Set(d, kNoMass), vshift = hn::Set(d, shift);
    for (size_t k = 0; k < size_t(b.padded); k += n) {
        V one_minus, one_plus;
        cos_pair(d, hn::LoadU(d, b.mu_x() + k), hn::LoadU(d, b.mu_y() + k), hn::LoadU(d, b.mu_z() + k), w, one_minus,
                 one_plus);
        const V scale = hn::LoadU(d, b.scale() + k);
        const V e = hn::IfThenElse(hn::Gt(scale, zero), hn::Neg(hn::Mul(hn::LoadU(d, b.kappa() + k), one_minus)), no_mass);
        vmax = hn::Max(vmax, e);
        sum = hn::MulAdd(scale, hn::Exp(d, hn::Sub(e, vshift)), sum);
    }
    max_exponent = hn::GetLane(hn::MaxOfLanes(d, vmax));
    return hn::GetLane(hn::SumOfLanes(d, sum));
}

ScaledSum LobeBlockEval(const LobeBlock& b, const Vec3f& w) {
    ScaledSum s;
    float max_exponent;
    s.sum = block_sum(b, w, 0.f, max_exponent);
    if (!(max_exponent > kNoMass)) return ScaledSum();
    s.max_exponent = 0.f;
    // Every lobe far below float range: again relative to the largest, so the ratios survive.
    if (s.sum < 1e-30f) {
        s.sum = block_sum(b, w, max_exponent, max_exponent);
        s.max_exponent = max_exponent;
    }
    return s;
}

// (1 - e^-x) / x: the series below 0.1 (remainder < 2e-9 relative), the exponential above.
HWY_INLINE V one_minus_exp_over(Tag d, V x, V e, V inv_x) {
    const V series = hn::MulAdd(
        x, hn::MulAdd(x, hn::MulAdd(x, hn::MulAdd(x, hn::Set(d, 1.f / 120.f), hn::Set(d, -1.f / 24.f)), hn::Set(d, 1.f / 6.f)),
                      hn::Set(d, -0.5f)),
        hn::Set(d, 1.f));
    return hn::IfThenElse(hn::Lt(x, hn::Set(d, 0.1f)), series, hn::Mul(hn::Sub(hn::Set(d, 1.f), e), inv_x));
}

struct PairOut {
    float* mass;
    float* kappa12;
    float* expm1;
};

// Pairs (k .. k + lanes, j): their masses e^(-shift) and kappa_12; returns the exponents E_kj (kNoMass
// where the leaf lane has no mass).
HWY_INLINE V pair_chunk(Tag d, V ka, V scale, V one_minus, V one_plus, float kb, float scale_b, V vshift,
                        const PairOut& out, size_t at) {
    const V vkb = hn::Set(d, kb), tiny = hn::Set(d, 1e-12f);
    const V kk = hn::Mul(ka, vkb), diff = hn::Sub(ka, vkb);
    // kappa_12 = |ka mu_a + kb mu_b| and E = kappa_12 - ka - kb = -2 ka kb (1 - cos) / (kappa_12 + ka + kb).
    const V k12 = hn::Sqrt(hn::MulAdd(hn::Add(kk, kk), one_plus, hn::Mul(diff, diff)));
    const V den = hn::Max(hn::Add(k12, hn::Add(ka, vkb)), tiny);
    const V x = hn::Add(k12, k12), xc = hn::Max(x, tiny);
    const V r = hn::Div(hn::Set(d, 1.f), hn::Mul(xc, den));  // the pair's one division: 1 / x and 1 / den
    const V e = hn::Exp(d, hn::Neg(x));
    const V h = one_minus_exp_over(d, x, e, hn::Mul(den, r));  // 1 / c~(kappa_12) = 4 pi h
    // Pad lanes (scale 0) get the exponent of no mass: e^(it - shift) is 0, never 0 x inf.
    const V exponent = hn::IfThenElse(hn::Gt(scale, hn::Zero(d)),
                                      hn::Mul(hn::Mul(hn::Set(d, -2.f), hn::Mul(kk, one_minus)), hn::Mul(xc, r)),
                                      hn::Set(d, kNoMass));
    const V m0 = hn::Mul(hn::Mul(scale, hn::Set(d, scale_b * 4.f * 3.14159265358979323846f)), h);
    hn::StoreU(hn::Mul(m0, hn::Exp(d, hn::Sub(exponent, vshift))), d, out.mass + at);
    hn::StoreU(k12, d, out.kappa12 + at);
    hn::StoreU(hn::Neg(hn::Mul(x, h)), d, out.expm1 + at);
    return exponent;
}

float product_pass(const LobeBlock& leaf, const PairedLobes& phase, const Vec3f& dir, float shift,
                   const PairOut& out, float& max_exponent) {
    const Tag d;
    const size_t n = hn::Lanes(d);
    V vmax = hn::Set(d, kNoMass);
    const V vshift = hn::Set(d, shift);
    for (size_t k = 0; k < size_t(leaf.padded); k += n) {
        V one_minus, one_plus;
        cos_pair(d, hn::LoadU(d, leaf.mu_x() + k), hn::LoadU(d, leaf.mu_y() + k), hn::LoadU(d, leaf.mu_z() + k), dir,
                 one_minus, one_plus);
        const V ka = hn::LoadU(d, leaf.kappa() + k), scale = hn::LoadU(d, leaf.scale() + k);
        for (int j = 0; j < phase.count; ++j) {
            // Lobe j sits on sign_j d: its 1 - cos to mu_k is 1 -+ mu_k . d.
            const bool forward = phase.sign[j] > 0.f;
            const V e = pair_chunk(d, ka, scale, forward ? one_minus : one_plus, forward ? one_plus : one_minus,
                                   phase.kappa[j], phase.scale[j], vshift, out, size_t(j) * size_t(leaf.padded) + k);
            vmax = hn::Max(vmax, e);
        }
    }
    max_exponent = hn::GetLane(hn::MaxOfLanes(d, vmax));
    const size_t pairs = size_t(phase.count) * size_t(leaf.padded);
    V sum = hn::Zero(d);
    for (size_t i = 0; i < pairs; i += n) sum = hn::Add(sum, hn::LoadU(d, out.mass + i));
    return hn::GetLane(hn::SumOfLanes(d, sum));
}

ScaledSum LobeProductPairs(const LobeBlock& leaf, const PairedLobes& phase, const Vec3f& dir, float* mass,
                           float* kappa12, float* expm1) {
    const PairOut out{mass, kappa12, expm1};
    ScaledSum s;
    float max_exponent;
    s.sum = product_pass(leaf, phase, dir, 0.f, out, max_exponent);
    if (!(max_exponent > kNoMass)) return ScaledSum();
    s.max_exponent = 0.f;
    if (s.sum < 1e-30f) {  // every pair far below float range: again relative to the largest
        s.sum = product_pass(leaf, phase, dir, max_exponent, out, max_exponent);
        s.max_exponent = max_exponent;
    }
    return s;
}

}  // namespace HWY_NAMESPACE
}  // namespace volguide
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace volguide {

HWY_EXPORT(LobeBlockEval);
HWY_EXPORT(LobeProductPairs);

ScaledSum lobe_block_eval(const LobeBlock& b, const Vec3f& w) {
    if (b.empty()) return ScaledSum();
    return HWY_DYNAMIC_DISPATCH(LobeBlockEval)(b, w);
}

ScaledSum lobe_product_pairs(const LobeBlock& leaf, const PairedLobes& phase, const Vec3f& d, float* mass,
                             float* kappa12, float* expm1_2k12) {
    if (leaf.empty() || phase.count == 0) return ScaledSum();
    return HWY_DYNAMIC_DISPATCH(LobeProductPairs)(leaf, phase, d, mass, kappa12, expm1_2k12);
}

}  // namespace volguide
#endif  // HWY_ONCE
