#include "volguide/guiding/inscatter_cache.h"

#include <cmath>

#include "volguide/core/parallel.h"
#include "volguide/vmm/vmf_sum.h"
#include "volguide/vmm/vmm.h"

namespace volguide {

InscatterCache::InscatterCache(const GuidingField& field, const PhaseVmm& phase) : field_(&field) {
    const std::vector<GuidingLeaf>& leaves = field.leaves();
    // Convolve in parallel into per-leaf lists, then concatenate in leaf order.
    struct Lobe {
        float mu_x, mu_y, mu_z, kappa, scale;
    };
    std::vector<std::vector<Lobe>> per_leaf(leaves.size());
    parallel_for(size_t(0), leaves.size(), [&](size_t l) {
        const GuidingLeaf& leaf = leaves[l];
        if (!leaf.valid) return;
        const auto mixture = convolve(leaf.vmm, phase);
        std::vector<Lobe>& out = per_leaf[l];
        out.reserve(size_t(mixture.count));
        for (int k = 0; k < mixture.count; ++k) {
            const VmfLobe lobe = mixture.lobe(k);
            if (!(mixture.weight[k] > 0.f)) continue;
            out.push_back({lobe.mu.x, lobe.mu.y, lobe.mu.z, lobe.kappa, mixture.weight[k] * lobe.norm});
        }
    });
    first_.resize(leaves.size() + 1, 0);
    size_t total = 0;
    for (size_t l = 0; l < leaves.size(); ++l) {
        first_[l] = uint32_t(total);
        total += per_leaf[l].size();
    }
    first_[leaves.size()] = uint32_t(total);
    for (auto* v : {&mu_x_, &mu_y_, &mu_z_, &kappa_, &scale_}) v->reserve(total);
    for (const auto& v : per_leaf)
        for (const Lobe& b : v) {
            mu_x_.push_back(b.mu_x);
            mu_y_.push_back(b.mu_y);
            mu_z_.push_back(b.mu_z);
            kappa_.push_back(b.kappa);
            scale_.push_back(b.scale);
        }
}

Color3 InscatterCache::inscattered(int leaf, const Vec3f& w) const {
    if (!field_ || leaf < 0) return Color3(0.f);
    const GuidingLeaf& gl = field_->leaves()[size_t(leaf)];
    if (!gl.valid) return Color3(0.f);
    const uint32_t i = first_[size_t(leaf)];
    const int n = int(first_[size_t(leaf) + 1] - i);
    return gl.fluence * vmf_sum(mu_x_.data() + i, mu_y_.data() + i, mu_z_.data() + i, kappa_.data() + i, nullptr,
                                scale_.data() + i, n, w);
}

Color3 InscatterCache::inscattered(const Point3f& x, const Vec3f& w) const {
    if (!field_ || field_->empty()) return Color3(0.f);
    return inscattered(field_->tree().leaf_at(x), w);
}

size_t InscatterCache::memory_bytes() const {
    return sizeof(*this) + first_.capacity() * sizeof(uint32_t) +
           (mu_x_.capacity() + mu_y_.capacity() + mu_z_.capacity() + kappa_.capacity() + scale_.capacity()) * sizeof(float);
}

}  // namespace volguide
