// Null-collision estimators of the heterogeneous medium (theory.md §2.2-2.4, §2.6), all driven by
// a DDA over the majorant grid in the sigma_t volume's local coordinates (t is the world ray
// parameter throughout, so distances need no conversion).
#include "volguide/media/dda.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

namespace {

inline float exponential(Sampler& s) { return -std::log1p(-s.next_1d()); }
inline Color3 abs(const Color3& c) { return {std::abs(c.r), std::abs(c.g), std::abs(c.b)}; }
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

// Spectral tracking (Kutz et al. 2017): the event probabilities weigh each channel by the path
// weight, i.e. the throughput on entry (as channel probabilities) times the tracking weight w
// accumulated here; w alone is returned.
FreeFlightSample HeterogeneousMedium::sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                                         Sampler& sampler, TrackingCounts* counts) const {
    FreeFlightSample fs;
    fs.t = tmax;
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) return fs;

    const Color3 entry = channel_probabilities(throughput);
    Color3 w(1.f);
    bool ended = false;  // scattered, or the tracking weight vanished
    for_each_tentative_collision(o, d, t0, t1, sampler, counts, [&](float t, float mu) {
        const Color3 sigma_t = sigma_t_local(o + d * t);
        const Color3 sigma_n = Color3(mu) - sigma_t;
        const Color3 path_w = w * entry;
        const float pc = abs(sigma_t * path_w).average(), pn = abs(sigma_n * path_w).average();
        const float z = pc + pn;
        if (!(z > 0.f)) {  // the tracking weight vanished: nothing can be carried further
            fs.weight = fs.flight_weight = Color3(0.f);
            ended = true;
            return false;
        }
        if (sampler.next_1d() * z < pc) {
            if (counts) ++counts->real_collisions;
            const Point3f p = ray(t);
            fs.scatter_at(ray, t, p, this, {sigma_t, sigma_t * albedo_->eval(p)});
            fs.flight_weight = w * (z / (mu * pc));
            fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
            ended = true;
            return false;
        }
        if (counts) ++counts->null_collisions;
        w = w * sigma_n * (z / (mu * pn));
        return true;
    });
    if (ended) return fs;
    fs.weight = fs.flight_weight = w;
    return fs;
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
        if (!cell.control.is_black()) tr *= exp(cell.control * -(seg_end - seg_start));
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
