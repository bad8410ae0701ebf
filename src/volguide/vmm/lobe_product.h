#pragma once
// The product V_L(w) V_f(w) / Z of a leaf's lobe block (lobe_block.h) and a phase function's zonal
// lobes oriented on the travel direction d (docs/theory.md §3.7, §8.1): the direction decision's guide.
//  - build: the K x J pair masses in closed form, vectorised over the leaf's lobes (vmf_simd.h); the
//    pairs' mean directions are not formed (a sample forms the one it draws);
//  - sample: a pair by its mass, then that pair's lobe (mu_12 = (kappa_k mu_k + kappa_j mu_j) / kappa_12);
//  - pdf: in factorised form, V_L(w) V_f(w) / Z — K + J exponentials instead of K x J — which is the
//    density of the pairs' mixture exactly (a product of vMF lobes is a scaled vMF lobe, eq. 3.3), so
//    the pdf is the one sampled, to float rounding.
// No heap: fixed storage for 32 x 4 pairs (1.6 KB), filled only as far as the pairs go.
#include <array>

#include "volguide/vmm/lobe_block.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/vmf_simd.h"

namespace volguide {

// A phase function's zonal lobes prepared once per medium (what phase_vmm.h's oriented() rebuilt
// in double at every vertex): concentrations, scales w_j c~(kappa_j), signs, expm1(-2 kappa_j).
struct PhaseLobes {
    int count = 0;
    std::array<float, kPhaseVmmMaxLobes> kappa{}, scale{}, sign{}, expm1{}, weight{};
    // Every lobe below this concentration: the phase function is near-isotropic and the product is
    // the leaf's mixture (the phase factor varies by < 2 % over the sphere).
    static constexpr float kIsotropicKappa = 0.01f;
    bool isotropic() const;
    PairedLobes paired() const { return PairedLobes{count, kappa.data(), scale.data(), sign.data()}; }
};
PhaseLobes prepare_phase_lobes(const PhaseVmm& phase);

class LobeProduct {
  public:
    static constexpr int kMaxPairs = (kVmmMaxLobes + kLobeLanes - 1) / kLobeLanes * kLobeLanes * kPhaseVmmMaxLobes;

    // The product of `leaf` and `phase` on the travel direction d (both must outlive the product);
    // false when it has no finite positive mass (nothing to sample).
    bool build(const LobeBlock& leaf, const PhaseLobes& phase, const Vec3f& d);

    // A direction from the product with one 2-D random number (u.x picks the pair, rescaled).
    Vec3f sample(Point2f u) const;
    // The product's density at w.
    float pdf(const Vec3f& w) const;
    // Z = integral of V_L V_f over the sphere.
    double integral() const { return double(total_) * std::exp(double(max_exponent_)); }

    // The product as an ordinary mixture (inspection and tests; slow): pair (k, j) at k x J + j, the
    // order of vmm.h's product_into. Capacity kVmmMaxLobes x kPhaseVmmMaxLobes.
    VmfMixture<kVmmMaxLobes * kPhaseVmmMaxLobes> mixture() const;

  private:
    // Pair i's lobe: its mean direction and concentration.
    VmfLobe pair_lobe(int i) const;
    int pair_at(float& u) const;  // the pair u picks by mass, u rescaled to [0, 1)
    float mass(int i) const { return mass_[size_t(i)]; }

    LobeBlock leaf_;
    const PhaseLobes* phase_ = nullptr;
    Vec3f d_;
    int pairs_ = 0;
    float total_ = 0.f, max_exponent_ = 0.f;
    alignas(64) std::array<float, kMaxPairs> mass_;  // the pairs' masses, relative to e^max_exponent_
    alignas(64) std::array<float, kMaxPairs> kappa_;
    alignas(64) std::array<float, kMaxPairs> expm1_;
};

}  // namespace volguide
