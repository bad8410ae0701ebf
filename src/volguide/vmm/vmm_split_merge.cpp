#include "volguide/vmm/vmm_split_merge.h"

#include <cmath>
#include <vector>

namespace volguide {

namespace {
// Log-likelihood of a mixture over weighted samples (weights as given, no normalisation).
template <int N>
double log_likelihood(const VmfMixture<N>& m, std::span<const DirectionalSample> samples) {
    double ll = 0.0;
    for (const DirectionalSample& s : samples)
        ll += s.weight * std::log(std::max(double(m.pdf(s.direction)), 1e-300));
    return ll;
}
}  // namespace

int split_lobes(Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings) {
    double weight_sum = 0.0;
    size_t usable = 0;
    for (const DirectionalSample& s : samples)
        if (s.weight > 0.f && std::isfinite(s.weight)) weight_sum += s.weight, ++usable;
    if (!(weight_sum > 0.0)) return 0;
    const double normaliser = double(usable) / weight_sum;  // weights in units of samples

    const Vmm before = vmm;
    std::vector<DirectionalSample> owned;
    int splits = 0;
    for (int k = 0; k < before.count && !vmm.full(); ++k) {
        if (before.weight[k] < settings.min_split_weight || before.kappa[k] >= 0.9f * settings.max_kappa)
            continue;
        // The samples lobe k explains, weighted by its responsibility.
        owned.clear();
        double evidence = 0.0;
        VmfLobe parent = before.lobe(k);
        for (const DirectionalSample& s : samples) {
            if (!(s.weight > 0.f) || !std::isfinite(s.weight)) continue;
            float pdf = before.pdf(s.direction);
            if (!(pdf > settings.min_mixture_pdf)) continue;
            double g = before.weight[k] * parent.eval(s.direction) / pdf;
            if (g < 1e-3) continue;
            owned.push_back({s.direction, float(s.weight * normaliser * g)});
            evidence += owned.back().weight;
        }
        if (owned.size() < 16) continue;
        // Two-lobe refit of those samples, seeded by k-means++.
        VmmFitSettings sub = settings;
        sub.split_and_merge = false;
        sub.initial_kappa = std::max(parent.kappa, settings.initial_kappa);
        Vmm children = kmeanspp_vmm(owned, 2, sub.initial_kappa, settings.init_seed + uint64_t(k));
        if (children.count < 2) continue;
        fit_vmm(children, owned, sub);
        VmfMixture<1> single;
        single.add_lobe(1.f, parent);
        double gain = log_likelihood(children, owned) - log_likelihood(single, owned);
        // BIC: a second lobe adds 4 parameters (axis 2, kappa, weight).
        if (gain <= settings.split_threshold * 0.5 * 4.0 * std::log(std::max(evidence, 2.0))) continue;
        vmm.set_lobe(k, before.weight[k] * children.weight[0], children.lobe(0));
        vmm.add_lobe(before.weight[k] * children.weight[1], children.lobe(1));
        ++splits;
    }
    return splits;
}

double merge_cost(const WeightedLobe& a, const WeightedLobe& b) {
    WeightedLobe m = merge_lobes(a, b);
    auto s = [](const VmfLobe& x, const VmfLobe& y) { return vmf_product(x, y).scale; };
    double wa = a.weight, wb = b.weight, wm = m.weight;
    double ff = wa * wa * s(a.lobe, a.lobe) + 2.0 * wa * wb * s(a.lobe, b.lobe) + wb * wb * s(b.lobe, b.lobe);
    double fg = wm * (wa * s(a.lobe, m.lobe) + wb * s(b.lobe, m.lobe));
    double gg = wm * wm * s(m.lobe, m.lobe);
    return ff > 0.0 ? std::max(ff - 2.0 * fg + gg, 0.0) / ff : 0.0;
}

int merge_redundant_lobes(Vmm& vmm, const VmmFitSettings& settings) {
    int merges = 0;
    while (vmm.count > std::max(settings.min_lobes, 1)) {
        double best = settings.merge_threshold;
        int bi = -1, bj = -1;
        for (int i = 0; i < vmm.count; ++i)
            for (int j = i + 1; j < vmm.count; ++j) {
                double c = merge_cost({vmm.weight[i], vmm.lobe(i)}, {vmm.weight[j], vmm.lobe(j)});
                if (c < best) {
                    best = c;
                    bi = i;
                    bj = j;
                }
            }
        if (bi < 0) break;
        vmm.merge(bi, bj);
        ++merges;
    }
    return merges;
}

}  // namespace volguide
