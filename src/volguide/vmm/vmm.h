#pragma once
// Mixture of von Mises-Fisher lobes with a fixed maximum lobe count (docs/theory.md §3.6), stored as a
// structure of arrays so that evaluation streams through contiguous floats. A value type: no heap,
// no virtuals; copying a 32-lobe mixture copies 0.8 KB.
//
// Products and convolutions return mixtures whose capacity is the product of the inputs'
// capacities (K x J lobes), so nothing is ever truncated.
#include <array>
#include <cassert>

#include "volguide/vmm/vmf.h"
#include "volguide/vmm/vmf_sum.h"

namespace volguide {

// Default capacity of a radiance mixture (docs/theory.md §15: 8 lobes by default, at most 32).
inline constexpr int kVmmMaxLobes = 32;

// Moment-matched merge of two weighted lobes (docs/theory.md §3.6): weights add, the weighted mean
// vectors r = w A3(kappa) mu add, and kappa = A3^-1(|r| / w).
struct WeightedLobe {
    float weight = 0.f;
    VmfLobe lobe;
};
WeightedLobe merge_lobes(const WeightedLobe& a, const WeightedLobe& b);

template <int MaxLobes>
struct VmfMixture {
    static constexpr int kCapacity = MaxLobes;

    int count = 0;
    std::array<float, MaxLobes> weight;  // sum to 1 for a normalised mixture
    std::array<float, MaxLobes> mu_x, mu_y, mu_z;
    std::array<float, MaxLobes> kappa;
    std::array<float, MaxLobes> norm;  // c~(kappa), cached

    // Empty, every slot zero (so whole mixtures compare and serialise deterministically).
    VmfMixture() : weight{}, mu_x{}, mu_y{}, mu_z{}, kappa{}, norm{} {}
    // Empty with the slots beyond `count` left unset: for scratch mixtures that are filled at once
    // (a guided direction sampler's product, 3.5 KB per medium vertex, where zeroing showed up).
    // Nothing here reads a slot at or beyond `count`.
    struct Uninitialized {};
    explicit VmfMixture(Uninitialized) {}

    int size() const { return count; }
    bool full() const { return count == MaxLobes; }

    VmfLobe lobe(int k) const {
        VmfLobe l;
        l.mu = {mu_x[k], mu_y[k], mu_z[k]};
        l.kappa = kappa[k];
        l.norm = norm[k];
        return l;
    }
    void set_lobe(int k, float w, const VmfLobe& l) {
        weight[k] = w;
        mu_x[k] = l.mu.x;
        mu_y[k] = l.mu.y;
        mu_z[k] = l.mu.z;
        kappa[k] = l.kappa;
        norm[k] = l.norm;
    }
    // Appends a lobe; returns false (and changes nothing) when the mixture is full.
    bool add_lobe(float w, const VmfLobe& l) {
        if (count >= MaxLobes) return false;
        set_lobe(count++, w, l);
        return true;
    }
    // Removes lobe k, keeping the order of the others.
    void remove_lobe(int k) {
        for (int i = k; i + 1 < count; ++i) set_lobe(i, weight[i + 1], lobe(i + 1));
        --count;
    }
    // Replaces lobes a and b by their moment-matched merge (stored at min(a, b)).
    void merge(int a, int b) {
        if (a > b) std::swap(a, b);
        WeightedLobe m = merge_lobes({weight[a], lobe(a)}, {weight[b], lobe(b)});
        set_lobe(a, m.weight, m.lobe);
        remove_lobe(b);
    }

    double weight_sum() const {
        double s = 0.0;
        for (int k = 0; k < count; ++k) s += weight[k];
        return s;
    }
    // Rescales the weights to sum to one; returns the previous sum (0 leaves them unchanged).
    double normalize_weights() {
        double s = weight_sum();
        if (s > 0.0)
            for (int k = 0; k < count; ++k) weight[k] = float(weight[k] / s);
        return s;
    }

    // sum_k weight_k v_k(w). For a normalised mixture this is the pdf per unit solid angle.
    // Four lobes at a time (vmf_sum.h: its exp is within 2 ulp of std::exp).
    float eval(const Vec3f& w) const {
        return vmf_sum(mu_x.data(), mu_y.data(), mu_z.data(), kappa.data(), weight.data(), norm.data(), count, w);
    }
    float pdf(const Vec3f& w) const { return eval(w); }

    // Picks lobe k with probability weight_k and rescales u to [0, 1) for reuse (docs/theory.md §3.6).
    int select_lobe(float& u) const {
        for (int k = 0; k + 1 < count; ++k) {
            if (u < weight[k]) {
                u = std::min(u / weight[k], OneMinusEpsilon);
                return k;
            }
            u -= weight[k];
        }
        // Last lobe takes the remainder (absorbs rounding of the weight sum).
        int last = count - 1;
        u = weight[last] > 0.f ? std::clamp(u / weight[last], 0.f, OneMinusEpsilon) : 0.f;
        return last;
    }
    // Samples a direction from a normalised mixture with one 2-D random number. An empty mixture
    // has pdf 0 everywhere and must not be sampled (asserted; release builds return +z).
    Vec3f sample(Point2f u) const {
        assert(count > 0);
        if (count <= 0) return {0.f, 0.f, 1.f};
        int k = select_lobe(u.x);
        return lobe(k).sample(u);
    }

    // Weighted mean direction vector sum_k w_k A3(kappa_k) mu_k (its length is the mean cosine).
    Vec3f mean_vector() const {
        Vec3d r(0.0);
        for (int k = 0; k < count; ++k)
            r += Vec3d(lobe(k).mu) * (double(weight[k]) * vmf_mean_cosine(kappa[k]));
        return Vec3f(r);
    }
};

using Vmm = VmfMixture<kVmmMaxLobes>;

// A rotation-invariant kernel (e.g. a phase function): lobes centred on sign * axis, where the
// axis is only known at query time. Used for convolutions and products with the phase function.
template <int MaxLobes>
struct ZonalMixture {
    static constexpr int kCapacity = MaxLobes;
    int count = 0;
    std::array<float, MaxLobes> weight{};
    std::array<float, MaxLobes> kappa{};
    std::array<float, MaxLobes> sign{};  // +1: centred on the axis, -1: on its opposite

    // The kernel as an ordinary mixture around a concrete axis.
    VmfMixture<MaxLobes> oriented(const Vec3f& axis) const {
        VmfMixture<MaxLobes> m;
        for (int j = 0; j < count; ++j) m.add_lobe(weight[j], VmfLobe(axis * sign[j], kappa[j]));
        return m;
    }
};

// Product of two mixtures into `out` (capacity >= the inputs' lobe counts multiplied): K x J lobes
// with weights w_k w'_j s_kj, normalised. Returns Z = sum_kj w_k w'_j s_kj = the integral of the
// product over the sphere. If Z underflows to 0 (or is NaN) `out` is left empty (the caller must
// fall back to another strategy). Writes in place, so a caller's fixed storage is filled without
// temporaries.
// (GCC 12 warns that `raw` may be read uninitialised in the 1 x 1 instantiation: it cannot see that
// raw[i] is written for every i < out.count.)
#pragma GCC diagnostic push
#if !defined(__clang__)  // a GCC-only warning group: clang would warn that it does not know it
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
template <int A, int B, int C>
double product_into(const VmfMixture<A>& a, const VmfMixture<B>& b, VmfMixture<C>& out) {
    static_assert(C >= A * B, "product_into: output capacity below A x B");
    out.count = 0;
    double z = 0.0;
    std::array<double, A * B> raw;  // unnormalised weights (may be far below float range)
    // Lobes of b on the axis of the lobe before them (a phase VMM's, all on +-the travel direction)
    // share the angle to each lobe of a: computed once (the same bits as vmf_product(la, lb)).
    auto same_axis = [&b](int j) {
        return j > 0 && b.mu_x[j] == b.mu_x[j - 1] && b.mu_y[j] == b.mu_y[j - 1] && b.mu_z[j] == b.mu_z[j - 1];
    };
    for (int k = 0; k < a.count; ++k) {
        VmfLobe la = a.lobe(k);
        VmfCosPair c;
        for (int j = 0; j < b.count; ++j) {
            const VmfLobe lb = b.lobe(j);
            if (!same_axis(j)) c = vmf_cos_pair(la.mu, lb.mu);
            VmfProduct p = vmf_product(la, lb, c);
            double w = double(a.weight[k]) * b.weight[j] * p.scale;
            raw[out.count] = w;
            out.add_lobe(0.f, p.lobe);
            z += w;
        }
    }
    if (!(z > 0.0)) {
        out.count = 0;
        return z;
    }
    for (int i = 0; i < out.count; ++i) out.weight[i] = float(raw[i] / z);
    return z;
}
#pragma GCC diagnostic pop

// The same as a value; `integral` receives Z.
template <int A, int B>
VmfMixture<A * B> product(const VmfMixture<A>& a, const VmfMixture<B>& b, double* integral = nullptr) {
    VmfMixture<A * B> out;
    const double z = product_into(a, b, out);
    if (integral) *integral = z;
    return out;
}

// Convolution with a single rotation-invariant vMF kernel of concentration kernel_kappa, each lobe
// approximated by A3(kappa') = A3(kappa) A3(kernel_kappa) (docs/theory.md eq. 3.5).
template <int N>
VmfMixture<N> convolve(const VmfMixture<N>& m, float kernel_kappa) {
    VmfMixture<N> out = m;
    for (int k = 0; k < m.count; ++k)
        out.set_lobe(k, m.weight[k], VmfLobe(m.lobe(k).mu, vmf_convolved_kappa(m.kappa[k], kernel_kappa)));
    return out;
}

// Convolution with a zonal kernel (docs/theory.md eq. 5.1): (f * L)(w) = integral f(w . w') L(w') dw'
// with f = sum_j w_j v(. | sign_j w, kappa_j). Lobe (k, j) has weight pi_k w_j, axis sign_j mu_k
// and the A3-product concentration.
template <int N, int J>
VmfMixture<N * J> convolve(const VmfMixture<N>& m, const ZonalMixture<J>& kernel) {
    VmfMixture<N * J> out;
    for (int k = 0; k < m.count; ++k) {
        Vec3f mu = m.lobe(k).mu;
        for (int j = 0; j < kernel.count; ++j)
            out.add_lobe(m.weight[k] * kernel.weight[j],
                         VmfLobe(mu * kernel.sign[j], vmf_convolved_kappa(m.kappa[k], kernel.kappa[j])));
    }
    return out;
}

// Exact value of the same convolution at direction w (docs/theory.md eq. 3.4): sum_kj pi_k w_j s_kj.
// Equals the normaliser Z of the product of m with kernel.oriented(w).
template <int N, int J>
double convolve_exact(const VmfMixture<N>& m, const ZonalMixture<J>& kernel, const Vec3f& w) {
    double sum = 0.0;
    for (int k = 0; k < m.count; ++k) {
        Vec3f mu = m.lobe(k).mu;
        for (int j = 0; j < kernel.count; ++j) {
            double omc = one_minus_cos(mu, w * kernel.sign[j]);
            sum += double(m.weight[k]) * kernel.weight[j] *
                   vmf_convolution_exact(m.kappa[k], kernel.kappa[j], omc);
        }
    }
    return sum;
}

}  // namespace volguide
