#include "volguide/vmm/lobe_product.h"

#include <algorithm>
#include <cmath>

namespace volguide {

bool PhaseLobes::isotropic() const {
    for (int j = 0; j < count; ++j)
        if (!(kappa[size_t(j)] < kIsotropicKappa)) return false;
    return true;
}

PhaseLobes prepare_phase_lobes(const PhaseVmm& phase) {
    PhaseLobes p;
    p.count = phase.count;
    for (int j = 0; j < phase.count; ++j) {
        const size_t i = size_t(j);
        p.kappa[i] = phase.kappa[i];
        p.weight[i] = phase.weight[i];
        p.scale[i] = float(double(phase.weight[i]) * vmf_normalization(phase.kappa[i]));
        p.sign[i] = phase.sign[i] < 0.f ? -1.f : 1.f;
        p.expm1[i] = float(std::expm1(-2.0 * double(phase.kappa[i])));
    }
    return p;
}

bool LobeProduct::build(const LobeBlock& leaf, const PhaseLobes& phase, const Vec3f& d) {
    leaf_ = leaf;
    phase_ = &phase;
    d_ = d;
    pairs_ = leaf.padded * phase.count;
    // No running sums here: a vertex samples its guide at most once, and half of them never do (the
    // phase function's share); pair_at walks the masses when it does.
    const ScaledSum s = lobe_product_pairs(leaf, phase.paired(), d, mass_.data(), kappa_.data(), expm1_.data());
    total_ = s.sum;
    max_exponent_ = s.max_exponent;
    if (!(total_ > 0.f) || !std::isfinite(total_)) {
        pairs_ = 0;
        total_ = 0.f;
        return false;
    }
    return true;
}

int LobeProduct::pair_at(float& u) const {
    float x = u * total_;
    // The pair whose stretch of the masses holds x: pairs of no mass (pad lanes) are never picked.
    int last = -1;
    for (int i = 0; i < pairs_; ++i) {
        const float m = mass_[size_t(i)];
        if (!(m > 0.f)) continue;
        if (x < m) {
            u = std::clamp(x / m, 0.f, OneMinusEpsilon);
            return i;
        }
        x -= m;
        last = i;
    }
    // Rounding at the top (the masses summed in another order than the kernel's total): the last pair
    // with mass.
    u = OneMinusEpsilon;
    return last;
}

VmfLobe LobeProduct::pair_lobe(int i) const {
    const int k = i % leaf_.padded, j = i / leaf_.padded;
    const float ka = leaf_.kappa()[k], kb = phase_->kappa[size_t(j)] * phase_->sign[size_t(j)];
    const Vec3f m(ka * leaf_.mu_x()[k] + kb * d_.x, ka * leaf_.mu_y()[k] + kb * d_.y, ka * leaf_.mu_z()[k] + kb * d_.z);
    const float len = norm(m);
    VmfLobe l;
    l.kappa = kappa_[size_t(i)];
    l.mu = len > 0.f && l.kappa >= kVmfUniformKappa ? m / len : Vec3f(leaf_.mu_x()[k], leaf_.mu_y()[k], leaf_.mu_z()[k]);
    l.norm = float(vmf_normalization(l.kappa));
    return l;
}

Vec3f LobeProduct::sample(Point2f u) const {
    const int i = pair_at(u.x);
    const VmfLobe l = pair_lobe(i);
    return sample_vmf_prepared(l.mu, l.kappa, expm1_[size_t(i)], u);
}

float LobeProduct::pdf(const Vec3f& w) const {
    if (pairs_ == 0) return 0.f;
    const ScaledSum leaf = lobe_block_eval(leaf_, w);
    if (!(leaf.sum > 0.f)) return 0.f;
    // The phase lobes (at most four, on +-d): scalar.
    const float omc = std::min(0.5f * squared_norm(w - d_), 2.f), opc = std::min(0.5f * squared_norm(w + d_), 2.f);
    float e[kPhaseVmmMaxLobes], e_max = -INFINITY;
    for (int j = 0; j < phase_->count; ++j) {
        e[j] = -phase_->kappa[size_t(j)] * (phase_->sign[size_t(j)] > 0.f ? omc : opc);
        e_max = std::max(e_max, e[j]);
    }
    float phase = 0.f;
    for (int j = 0; j < phase_->count; ++j) phase += phase_->scale[size_t(j)] * std::exp(e[j] - e_max);
    // e^(E_L + E_f - E_max) <= 1: no pair's exponent at w exceeds its integral's (eq. 3.3).
    return leaf.sum * phase / total_ * std::exp(leaf.max_exponent + e_max - max_exponent_);
}

VmfMixture<kVmmMaxLobes * kPhaseVmmMaxLobes> LobeProduct::mixture() const {
    VmfMixture<kVmmMaxLobes * kPhaseVmmMaxLobes> m;
    const int J = phase_ ? phase_->count : 0;
    for (int k = 0; k < leaf_.count; ++k)
        for (int j = 0; j < J; ++j) {
            const int i = j * leaf_.padded + k;
            m.add_lobe(pairs_ ? mass_[size_t(i)] / total_ : 0.f, pair_lobe(i));
        }
    if (pairs_ == 0) m.count = 0;
    return m;
}

}  // namespace volguide
