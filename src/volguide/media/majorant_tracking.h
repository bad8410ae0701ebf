#pragma once
// Null-collision free flights as callbacks of a majorant walk (docs/theory.md §2.2, §7.7 H2): at each
// tentative collision a policy (media/collision_policy.h) chooses scatter or continue, and the
// tracking here owns the weights:
//   scatter:   flight weight = w * factor,    weight = flight weight * sigma_s(x)
//   continue:  w <- w * (mu - sigma_t(x)) * factor
// track_collisions takes the walk as a function of the per-collision callback, so that a medium's
// own free flight (spectral tracking over its inlined walk, media/tracking.cpp) and a caller's
// guided tracking over Medium::sample_majorant_walk (one indirect call per collision) are the
// same code.
#include <type_traits>

#include "volguide/media/collision_policy.h"
#include "volguide/media/medium.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

// The event probabilities weigh each channel by the path weight, i.e. the throughput on entry (as
// channel probabilities) times the tracking weight w accumulated here; w alone is returned.
// `walk(collide)` calls collide(const MajorantCollision&) at each tentative collision until it
// returns false. Before the first collision nothing is drawn here: a walk that finds no collision
// returns weight 1 at tmax.
template <class Policy, class Walk>
FreeFlightSample track_collisions(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                  Sampler& sampler, const Policy& policy, TrackingCounts* counts, Walk&& walk) {
    FreeFlightSample fs;
    fs.t = tmax;
    const Color3 entry = channel_probabilities(throughput);
    Color3 w(1.f);
    // The decision that ended the walk (Null: none did, the ray reached the segment's end) and, for
    // a scatter, its collision: the scatter is recorded after the walk, so that the per-collision
    // callback stays small. always_inline: GCC 12 otherwise keeps the callback out of line, a call
    // per tentative collision.
    CollisionDecision end{CollisionDecision::Event::Null};
    TentativeCollision scatter{};
    walk([&](const MajorantCollision& m) __attribute__((always_inline)) {
        TentativeCollision c{m.t, m.mu, m.sigma_t, Color3(0.f), w * entry};
        if constexpr (Policy::reads_scattering) c.sigma_s = c.sigma_t * medium.albedo(ray(m.t));
        end = policy(c, sampler);
        if (end.event == CollisionDecision::Event::Null) {
            if (counts) ++counts->null_collisions;
            w = w * (Color3(m.mu) - c.sigma_t) * end.factor;
            if (!w.is_black()) return true;
            end.event = CollisionDecision::Event::Vanish;  // sigma_t = mu in every channel that carried weight
        }
        if (end.event == CollisionDecision::Event::Scatter) scatter = c;
        return false;
    });
    switch (end.event) {
        case CollisionDecision::Event::Scatter: {
            if (counts) ++counts->real_collisions;
            const Point3f p = ray(scatter.t);
            if constexpr (!Policy::reads_scattering) scatter.sigma_s = scatter.sigma_t * medium.albedo(p);
            fs.scatter_at(ray, scatter.t, p, &medium, {scatter.sigma_t, scatter.sigma_s});
            fs.flight_weight = w * end.factor;
            fs.weight = fs.flight_weight * scatter.sigma_s;
            break;
        }
        case CollisionDecision::Event::Vanish:  // nothing can be carried further
            fs.weight = fs.flight_weight = Color3(0.f);
            break;
        case CollisionDecision::Event::Null:
            fs.weight = fs.flight_weight = w;
            break;
    }
    return fs;
}

// Guided null-collision tracking over the medium's majorant walk: P_s = probability(c) at each
// tentative collision c (GuidedTrackingPolicy: c's channel weights normalised, NaN -> the unguided
// probability, clamped to [0, 1]), called in order of increasing t. Medium::sample_free_flight's
// contract; `counts` (optional) counts null and real collisions (not cells).
template <class ScatterProbability>
FreeFlightSample guided_tracking(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                 Sampler& sampler, ScatterProbability&& probability, TrackingCounts* counts = nullptr) {
    const GuidedTrackingPolicy<std::remove_reference_t<ScatterProbability>> policy{probability};
    return track_collisions(medium, ray, tmax, throughput, sampler, policy, counts, [&](auto&& collide) {
        medium.sample_majorant_walk(ray, tmax, sampler, collide);
    });
}

}  // namespace volguide
