#pragma once
// The directional contrast of a mixture: chi2 = 4 pi ∫ V(w)^2 dw - 1, the chi-square divergence of the
// normalised VMM from the uniform density — the relative variance of the radiance it models over
// directions, i.e. the most a direction decision guided by it can gain over an isotropic one.
// tools/field_accuracy reports it per leaf (issue 56). A trust rule built on it (no trust below a
// contrast threshold) was measured and did not pay (bench/RESULTS.md, issue 56): it is not in the
// decisions.
#include "volguide/vmm/vmm.h"

namespace volguide {

// chi2 >= 0 of a normalised mixture (0 for the uniform density, and for an empty one).
double directional_contrast(const Vmm& vmm);

}  // namespace volguide
