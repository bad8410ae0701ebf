#include "volguide/vmm/vmm.h"

namespace volguide {

WeightedLobe merge_lobes(const WeightedLobe& a, const WeightedLobe& b) {
    double w = double(a.weight) + b.weight;
    if (!(w > 0.0)) return {0.f, a.lobe};
    Vec3d r = (Vec3d(a.lobe.mu) * (a.weight * vmf_mean_cosine(a.lobe.kappa)) +
               Vec3d(b.lobe.mu) * (b.weight * vmf_mean_cosine(b.lobe.kappa))) /
              w;
    double len = norm(r);
    // Opposite lobes of equal strength cancel: the merge is uniform, keep a's axis.
    Vec3f mu = len > 1e-12 ? Vec3f(r / len) : a.lobe.mu;
    // The cap keeps merges of lobes beyond the fitting cap (e.g. product lobes) exact.
    double cap = std::max({double(a.lobe.kappa), double(b.lobe.kappa), double(kVmfMaxKappa)});
    return {float(w), VmfLobe(mu, float(vmf_kappa_from_mean_cosine(len, cap)))};
}

}  // namespace volguide
