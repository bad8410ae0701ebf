#include "volguide/guiding/surface_guide.h"

#include <cmath>

#include "volguide/vmm/vmm_fast_product.h"

namespace volguide {

float cosine_lobe_kappa() {
    static const float kappa = float(vmf_kappa_from_mean_cosine(2.0 / 3.0));
    return kappa;
}

bool cosine_product(const Vmm& incident, const Vec3f& n, Vmm& out) {
    static const VmfLobe unit_cosine(Vec3f(0.f, 0.f, 1.f), cosine_lobe_kappa());
    VmfLobe cosine = unit_cosine;
    cosine.mu = n;
    return product_with_lobe_fast(incident, cosine, out) > 0.f;
}

}  // namespace volguide
