// Guided null-collision tracking of the heterogeneous medium (theory.md §7.7 H2): the DDA walk of
// spectral tracking (tracking.cpp), with the scatter/continue decision delegated to a CollisionGuide.
#include <algorithm>
#include <cmath>

#include "volguide/media/dda.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

FreeFlightSample HeterogeneousMedium::guided_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                                         Sampler& sampler, CollisionGuide& guide,
                                                         TrackingCounts* counts) const {
    FreeFlightSample fs;
    fs.t = tmax;
    Point3f o;
    Vec3f d;
    float t0, t1;
    if (!local_segment(ray, tmax, o, d, t0, t1)) return fs;

    const Color3 entry = channel_probabilities(throughput);
    Color3 w(1.f);
    bool ended = false;  // scattered, or the weight vanished
    for_each_tentative_collision(o, d, t0, t1, sampler, counts, [&](float t, float mu) {
        const Point3f p = ray(t);
        TentativeCollision c;
        c.t = t;
        c.mu = mu;
        c.sigma_t = sigma_t_local(o + d * t);
        c.sigma_s = c.sigma_t * albedo_->eval(p);
        c.channel_weights = channel_probabilities(w * entry);
        float ps = guide.scatter_probability(c);
        ps = std::isnan(ps) ? analog_scatter_probability(c) : std::clamp(ps, 0.f, 1.f);
        // u in [0, 1): P_s = 0 never scatters and P_s = 1 always does, so each branch's
        // division below is by a probability of at least ~1e-7 (weights stay finite).
        if (sampler.next_1d() < ps) {
            if (counts) ++counts->real_collisions;
            fs.scatter_at(ray, t, p, this, {c.sigma_t, c.sigma_s});
            fs.flight_weight = w * (1.f / (mu * ps));
            fs.weight = fs.flight_weight * c.sigma_s;
            ended = true;
            return false;
        }
        if (counts) ++counts->null_collisions;
        w = w * (Color3(mu) - c.sigma_t) * (1.f / (mu * (1.f - ps)));
        if (w.is_black()) {  // a null weight of zero (sigma_t = mu): nothing is carried further
            fs.weight = fs.flight_weight = Color3(0.f);
            ended = true;
            return false;
        }
        return true;
    });
    if (ended) return fs;
    fs.weight = fs.flight_weight = w;
    return fs;
}

}  // namespace volguide
