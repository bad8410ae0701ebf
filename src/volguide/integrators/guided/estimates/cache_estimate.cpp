#include "volguide/integrators/guided/estimates/cache_estimate.h"

#include <algorithm>
#include <cmath>

#include "volguide/integrators/volume_nee.h"
#include "volguide/media/homogeneous_transmittance.h"
#include "volguide/media/medium.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/scene.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

namespace {

// Integral over a step of length len of T(0, s) sigma_s ds for constant coefficients, per channel:
// sigma_s / sigma_t (1 - e^(-sigma_t len)), and sigma_s len when sigma_t = 0.
float step_weight(float sigma_s, float sigma_t, float len) {
    if (!(sigma_s > 0.f)) return 0.f;
    const float tau = sigma_t * len;
    return tau > 1e-4f ? sigma_s / sigma_t * -std::expm1(-tau) : sigma_s * len * (1.f - 0.5f * tau);
}

}  // namespace

CacheEstimator::CacheEstimator(const Scene& scene, const GuidingField& field) : scene_(scene), field_(field) {
    auto add = [&](const Medium* m) {
        if (!m) return;
        const float g = m->phase().mean_cosine();
        if (!inscatter_.count(g)) inscatter_.emplace(g, InscatterCache(field, hg_phase_vmm(g)));
    };
    add(scene.sensor().medium());
    for (const auto& shape : scene.shapes()) {
        add(shape->interior_medium());
        add(shape->exterior_medium());
    }
}

Color3 CacheEstimator::leaf_value(int leaf, const Vec3f& d, const Medium& medium, CacheQuantity quantity) const {
    if (quantity == CacheQuantity::Incident) return GuidingField::incident(field_.leaves()[size_t(leaf)], d);
    const auto it = inscatter_.find(medium.phase().mean_cosine());
    return it == inscatter_.end() ? Color3(0.f) : it->second.inscattered(leaf, d);
}

void CacheEstimator::march_segment(const Segment& segment, CacheQuantity quantity, Sampler& sampler, Color3& T,
                                   Color3& result) const {
    const Ray& ray = segment.ray;
    const Medium& medium = segment.medium;
    float t0 = segment.t0, t1 = segment.t1;
    const bool homogeneous = medium.is_homogeneous();
    if (!homogeneous) {  // nothing scatters or attenuates outside the grid's bounds
        float b0 = 0.f, b1 = 0.f;
        if (!medium.bbox().ray_intersect(ray, b0, b1)) return;
        t0 = std::max(t0, b0);
        t1 = std::min(t1, b1);
    }
    if (!(t1 > t0)) return;
    const MediumCoefficients constant = homogeneous ? medium.eval(ray.o) : MediumCoefficients{};
    const float max_step = homogeneous ? Infinity : norm(medium.bbox().extents()) / float(steps_per_diagonal);
    // Integrates (a, b) with the value of `leaf` (-1: outside the field, attenuation only).
    auto advance = [&](float a, float b, int leaf) {
        const Color3 value = leaf >= 0 ? leaf_value(leaf, ray.d, medium, quantity) : Color3(0.f);
        const int steps = homogeneous ? 1 : std::clamp(int(std::ceil((b - a) / max_step)), 1, 1 << 16);
        const float len = (b - a) / float(steps);
        for (int k = 0; k < steps; ++k) {
            const MediumCoefficients c =
                homogeneous ? constant : medium.eval(ray(a + (float(k) + sampler.next_1d()) * len));
            for (int ch = 0; ch < 3; ++ch) {
                result[ch] += T[ch] * step_weight(c.sigma_s[ch], c.sigma_t[ch], len) * value[ch];
                T[ch] *= transmittance_1(c.sigma_t[ch], len);
            }
        }
    };
    float t = t0;
    field_.tree().traverse(ray, t0, t1, [&](int leaf, float a, float b) {
        if (a > t) advance(t, a, -1);
        advance(std::max(a, t0), b, leaf);
        t = b;
        return T.max_value() > 1e-7f;
    });
    // Beyond the field there is nothing to add; a finite remainder still attenuates what follows.
    if (t < t1 && std::isfinite(t1) && T.max_value() > 1e-7f) advance(t, t1, -1);
}

Color3 CacheEstimator::estimate(const Ray& camera_ray, const Medium* medium, CacheQuantity quantity,
                                Sampler& sampler) const {
    Color3 T(1.f), result(0.f);
    Ray ray = camera_ray;
    for (int crossing = 0; crossing <= max_null_crossings; ++crossing) {
        SurfaceInteraction si;
        const bool hit = scene_.intersect(ray, si);
        const float tmax = hit ? si.t : ray.tmax;
        if (medium) march_segment({ray, 0.f, tmax, *medium}, quantity, sampler, T, result);
        // The estimate covers the media up to the first real surface (eq. 9.2 without its surface term).
        if (!hit || !si.shape->bsdf()->is_null() || !(T.max_value() > 1e-7f)) break;
        medium = medium_after(si, ray.d, medium);
        ray = si.spawn_ray(ray.d);
    }
    return result;
}

}  // namespace volguide
