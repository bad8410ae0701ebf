// Null-collision estimators of the heterogeneous medium (docs/theory.md §2.2-2.4, §2.6), all
// driven by a DDA over the majorant grid in the sigma_t volume's local coordinates (t is the world ray
// parameter throughout, so distances need no conversion).
#include "volguide/media/collision_policy.h"
#include "volguide/media/dda.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/homogeneous_transmittance.h"
#include "volguide/media/majorant_tracking.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

namespace {

inline float exponential(Sampler& s) { return -std::log1p(-s.next_1d()); }
inline float max_abs(const Color3& c) { return std::max({std::abs(c.r), std::abs(c.g), std::abs(c.b)}); }

// Unbiased Russian roulette on a transmittance estimate that has become small: survivors are
// reweighted so that the expectation is unchanged.
constexpr float kRouletteThreshold = 0.05f;
inline bool roulette(Color3& tr, Sampler& s) {
    const float m = max_abs(tr);
    if (m >= kRouletteThreshold) return true;
    if (m <= 0.f) return false;
    const float q = m / kRouletteThreshold;
    if (s.next_1d() >= q) return false;
    tr *= 1.f / q;
    return true;
}

}  // namespace

// Spectral tracking over the walk inlined (one instance of the template walk with the policy).
FreeFlightSample HeterogeneousMedium::sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                                         Sampler& sampler, TrackingCounts* counts) const {
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) {
        FreeFlightSample fs;
        fs.t = tmax;
        return fs;
    }
    return track_collisions(*this, ray, tmax, throughput, sampler, SpectralTrackingPolicy{}, counts,
                            [&](auto&& collide) __attribute__((always_inline)) {
                                for_each_tentative_collision(o, d, t0, t1, sampler, counts,
                                                             [&](float t, float mu) __attribute__((always_inline)) {
                                                                 return collide(
                                                                     MajorantCollision{t, mu, sigma_t_local(o + d * t)});
                                                             });
                            });
}

void HeterogeneousMedium::sample_majorant_walk(const Ray& ray, float tmax, Sampler& sampler,
                                               MajorantCallback collide) const {
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) return;
    for_each_tentative_collision(o, d, t0, t1, sampler, nullptr, [&](float t, float mu) {
        return collide(MajorantCollision{t, mu, sigma_t_local(o + d * t)});
    });
}

Color3 HeterogeneousMedium::transmittance(const Ray& ray, float tmax, Sampler& sampler) const {
    return estimator_ == TransmittanceEstimator::Ratio ? ratio_tracking(ray, tmax, sampler)
                                                       : residual_ratio_tracking(ray, tmax, sampler);
}

Color3 HeterogeneousMedium::ratio_tracking(const Ray& ray, float tmax, Sampler& sampler) const {
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) return Color3(1.f);
    Color3 tr(1.f);
    for_each_tentative_collision(o, d, t0, t1, sampler, nullptr, [&](float t, float mu) {
        tr *= Color3(1.f) - sigma_t_local(o + d * t) * (1.f / mu);
        if (roulette(tr, sampler)) return true;
        tr = Color3(0.f);  // killed by the roulette
        return false;
    });
    return tr;
}

Color3 HeterogeneousMedium::residual_ratio_tracking(const Ray& ray, float tmax, Sampler& sampler) const {
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) return Color3(1.f);
    const int* res = majorants_.res();
    const Vec3f cells{float(res[0]), float(res[1]), float(res[2])};
    Color3 tr(1.f);
    for (GridDda dda(o * cells, d * cells, res, t0, t1); !dda.done(); dda.advance()) {
        const MajorantCell& cell = majorants_.cell(dda.cell(0), dda.cell(1), dda.cell(2));
        const float seg_start = dda.t(), seg_end = dda.segment_end();
        if (!(seg_end > seg_start)) continue;
        // Control variate: the cell's per-channel mean extinction, integrated exactly.
        if (!cell.control.is_black()) tr *= transmittance_rgb(cell.control, seg_end - seg_start);
        const float rate = majorant_scale_ * cell.residual_rate;
        if (!(rate > 0.f)) continue;
        // The residual sigma_t - control, by ratio tracking with a Poisson process of this rate.
        float t = seg_start;
        while (true) {
            t += exponential(sampler) / rate;
            if (t >= seg_end) break;
            tr *= Color3(1.f) - (sigma_t_local(o + d * t) - cell.control) * (1.f / rate);
            if (!roulette(tr, sampler)) return Color3(0.f);
        }
    }
    return tr;
}

}  // namespace volguide
