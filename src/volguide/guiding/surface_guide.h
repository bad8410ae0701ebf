#pragma once
// The guide distribution of a diffuse surface vertex (volguide extension of docs/theory.md §5.7): the
// incident-radiance VMM of the kd leaf around the vertex, optionally multiplied by a vMF stand-in
// for the clamped cosine on the facing normal, normalised.
//
// Why the medium's field can guide surfaces: the field holds the incident radiance L(x, w) of the
// media (docs/theory.md §5.1), and radiance is continuous from a medium point to a surface point next
// to it, for the directions of the facing hemisphere. A wall of a fog-filled room therefore sees
// what the fog beside it sees; its leaf's VMM is the zero-variance target of the reflected
// direction up to the BSDF (f cos / pi for a diffuse surface). Leaves without medium photons are
// invalid and do not guide.
//
// The clamped cosine max(0, n . w) / pi is replaced by the vMF on n whose mean cosine is 2/3, the
// cosine lobe's own (A3(kappa) = 2/3, kappa ~ 2.96: the moment match, i.e. the vMF closest to the
// cosine lobe in KL(cos || vMF), which keeps the proposal wide where the cosine is). The product
// only shapes probabilities; the caller weights with the exact BSDF.
#include "volguide/vmm/vmm.h"

namespace volguide {

// Concentration of the vMF that stands for the clamped cosine lobe (A3(kappa) = 2/3).
float cosine_lobe_kappa();

// out = V(w) vMF(w | n, cosine_lobe_kappa()) / Z, the lobe-wise closed-form product (docs/theory.md
// §3.4) in single precision (vmm_fast_product.h). False (out empty) when the product has no
// finite positive mass: nothing to guide with.
// n must be unit length.
bool cosine_product(const Vmm& incident, const Vec3f& n, Vmm& out);

}  // namespace volguide
