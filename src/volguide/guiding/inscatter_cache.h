#pragma once
// The in-scattered radiance L~_i of every leaf of a guiding field for one phase function, prepared
// once: the A3 approximation (docs/theory.md eq. 5.1) convolves each leaf's incident VMM with the phase
// VMM, and that convolution (K x J lobes, each needing an inverse of A3) is the whole cost of a
// query. Prepared per (field, phase), a query is one leaf lookup and K x J lobe evaluations, cheap
// enough for the distance sampler's per-bin calls (issue 6, item 3).
//
// Lobes are stored flat (only the lobes that exist), so memory is proportional to the fitted lobes
// rather than to the mixtures' fixed capacity, as a structure of arrays summed four lobes at a time
// (vmf_sum.h).
#include <cstdint>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

class InscatterCache {
public:
    InscatterCache() = default;
    // Convolves every valid leaf (in parallel; the result does not depend on the thread count).
    // The field must outlive the cache.
    InscatterCache(const GuidingField& field, const PhaseVmm& phase);

    // L~_i(x, w) for a ray travelling along w; 0 outside the field or in invalid leaves. Equals
    // field.inscattered(x, w, phase, InscatterMode::A3) up to float rounding.
    Color3 inscattered(const Point3f& x, const Vec3f& w) const;
    // The same for a known leaf index (the distance sampler already has it from the traversal).
    Color3 inscattered(int leaf, const Vec3f& w) const;

    size_t memory_bytes() const;

private:
    const GuidingField* field_ = nullptr;
    std::vector<uint32_t> first_;  // leaf l's lobes are [first_[l], first_[l + 1]) of the arrays below
    // Structure of arrays, for vmf_sum's four lobes at a time; weight * c~(kappa) folded into `scale_`.
    std::vector<float> mu_x_, mu_y_, mu_z_, kappa_, scale_;
};

}  // namespace volguide
