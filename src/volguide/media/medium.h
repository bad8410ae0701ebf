#pragma once
// Participating media. A Medium owns its coefficients (homogeneous values or grid volumes, times
// `scale`), its phase function, and the unbiased estimators the integrators use:
//  - sample_free_flight: closed-form distance sampling (homogeneous), or a null-collision walk
//    over a majorant grid (heterogeneous) whose scatter decisions are spectral tracking's;
//  - transmittance: exact for homogeneous media (media/homogeneous_transmittance.h), ratio /
//    residual ratio tracking for heterogeneous ones;
//  - sample_majorant_walk (pbrt-v4's SampleT_maj shape): the tentative collisions of the majorant
//    walk handed to the caller one at a time, for decisions the medium does not make itself
//    (guided null-collision tracking, media/majorant_tracking.h; the per-segment scatter decision).
// Every estimator is unbiased for any majorant that bounds sigma_t; a looser majorant only costs
// time.
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "volguide/core/bbox.h"
#include "volguide/core/color.h"
#include "volguide/core/function_ref.h"
#include "volguide/core/object.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/geometry/interaction.h"
#include "volguide/media/phase.h"

namespace volguide {

class Medium;

struct MediumCoefficients {
    Color3 sigma_t;  // extinction (1/length), already multiplied by `scale`
    Color3 sigma_s;  // scattering = albedo * sigma_t
};

// A real scattering vertex inside a medium (n = 0: no surface).
struct MediumInteraction : Interaction {
    Vec3f wi;  // world space, towards the previous vertex (= -ray.d)
    MediumCoefficients coeffs;
    const Medium* medium = nullptr;
};

struct FreeFlightSample {
    bool scattered = false;  // true: a real scattering event at t < tmax; false: the ray reached tmax
    float t = Infinity;
    // Multiply the path throughput by this. With it the estimator is unbiased: it holds the
    // transmittance/pdf ratio of the tracking and, at a scattering event, sigma_s over the
    // probability density of stopping there (for monochromatic media simply the albedo).
    Color3 weight{1.f};
    // At a scattering event: the same ratio without sigma_s (weight = flight_weight * sigma_s), i.e.
    // the collision estimator's 1/sigma_t in expectation. The photon pass deposits with it: flux
    // arriving at the collision, before the albedo (docs/theory.md §5.2). On escape: equal to weight.
    Color3 flight_weight{1.f};
    MediumInteraction mi;  // valid when scattered

    // Records a real scattering event at p = ray(t) with the coefficients there (weights are the
    // caller's).
    void scatter_at(const Ray& ray, float t_event, const Point3f& p, const Medium* medium,
                    const MediumCoefficients& coeffs) {
        scattered = true;
        t = t_event;
        mi.p = p;
        mi.t = t_event;
        mi.wi = -ray.d;
        mi.medium = medium;
        mi.coeffs = coeffs;
    }
};

// A stretch of ray over which a medium is summarised by constants: the guided distance sampler's
// proxy coefficients (docs/theory.md §7.7 H1). They only shape probabilities, never weights.
struct ProxySegment {
    float t0, t1;
    Color3 sigma_t;  // per channel: exact (homogeneous) or the cell's mean (heterogeneous)
    float albedo;    // scalar: mean sigma_s / mean sigma_t over the channels (docs/theory.md §7.8)
};

// A tentative collision of a majorant walk: its ray parameter, the majorant rate mu of the
// majorant segment it lies in (a homogeneous medium is one segment, a heterogeneous one a segment
// per majorant cell crossed) and the true extinction there. The collisions form a Poisson process
// of rate mu along the ray, so the density of the first one at t is mu T_maj(t): weights computed as
// ratios against mu need no majorant transmittance.
struct MajorantCollision {
    float t;
    float mu;
    Color3 sigma_t;
};
// Called at each tentative collision in order of increasing t; returns false to end the walk. It may
// draw from the walk's sampler (the walk draws the next collision's optical depth after it returns).
using MajorantCallback = FunctionRef<bool(const MajorantCollision&)>;

// The majorant walk of constant extinction over (0, tmax): one segment at mu = the largest channel
// of sigma_t (exact for grey sigma_t; chromatic ones see null collisions for the thinner channels).
inline void walk_constant_majorant(const Color3& sigma_t, float tmax, Sampler& sampler, MajorantCallback collide) {
    const float mu = sigma_t.max_value();
    if (!(mu > 0.f)) return;
    float t = 0.f;
    while (true) {
        t += -std::log1p(-sampler.next_1d()) / mu;
        if (!(t < tmax) || !collide(MajorantCollision{t, mu, sigma_t})) return;
    }
}

// Event counters of one tracking call (for benchmarks and tests).
struct TrackingCounts {
    uint64_t null_collisions = 0;
    uint64_t real_collisions = 0;
    uint64_t cells = 0;  // majorant cells visited
};

class Medium : public Object {
public:
    const PhaseFunction& phase() const { return *phase_; }
    const std::shared_ptr<PhaseFunction>& phase_ptr() const { return phase_; }

    // Coefficients at a world-space point.
    virtual MediumCoefficients eval(const Point3f& p) const = 0;
    // Samples the next real scattering event along ray.o + t ray.d, t in (0, tmax); tmax may be
    // infinite (then the ray must scatter or be absorbed, or leave the medium's bounds).
    // `throughput` is the path's current throughput: chromatic media choose the channel that drives
    // the decision in proportion to it (media/spectral_mis.h); it does not scale the returned weight.
    virtual FreeFlightSample sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                                Sampler& sampler) const = 0;
    // The majorant walk over t in (0, tmax), tmax finite or not: `collide` at each tentative
    // collision until it returns false or the walk leaves (0, tmax) or the medium's bounds. The
    // walk draws one random number per collision (the optical depth to the next) before the first
    // and after each collision that continues. Deciding, weighting and counting are the callback's.
    virtual void sample_majorant_walk(const Ray& ray, float tmax, Sampler& sampler, MajorantCallback collide) const = 0;
    // The single-scattering albedo sigma_s / sigma_t at p (sigma_s = sigma_t * albedo): what a
    // majorant walk's callback multiplies in at a scatter.
    virtual Color3 albedo(const Point3f& p) const = 0;
    // Whether free flights walk tentative collisions (a null-collision walk) rather than being
    // sampled in closed form.
    virtual bool tracks_null_collisions() const = 0;
    // Unbiased estimate of the transmittance over t in (0, tmax).
    virtual Color3 transmittance(const Ray& ray, float tmax, Sampler& sampler) const = 0;

    // Appends to `out` segments tiling (t0, t1) in order (t1 finite) with proxy coefficients: one for
    // a homogeneous medium, one per majorant cell crossed (and zero-coefficient stretches outside
    // the grid) for a heterogeneous one.
    virtual void proxy_segments(const Ray& ray, float t0, float t1, std::vector<ProxySegment>& out) const = 0;
    // The proxy coefficients of every segment of every ray where they are one constant (a homogeneous
    // medium with a constant albedo): what proxy_segments appends for any t0 < t1, its interval aside,
    // so that a caller cutting many segments asks once. False (nothing written) where they vary.
    virtual bool constant_proxy(ProxySegment& /*proxy*/) const { return false; }

    virtual bool is_homogeneous() const = 0;
    // Where sigma_t can be non-zero (infinite for homogeneous media).
    virtual BBox3f bbox() const = 0;
    // Mitsuba's `sample_emitters` (default true): whether integrators do next-event estimation at
    // scattering vertices inside this medium.
    bool sample_emitters() const { return sample_emitters_; }

protected:
    std::shared_ptr<PhaseFunction> phase_;
    bool sample_emitters_ = true;
};

}  // namespace volguide
