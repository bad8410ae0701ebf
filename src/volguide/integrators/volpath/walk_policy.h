#pragma once
// The one interface through which what guiding, training and guided RR/splitting add enters
// volpath's walk (volpath_walk.h). The walk asks its policy for every decision:
//  - distance: where along the ray in a medium the next real scattering happens (the contract of
//    Medium::sample_free_flight);
//  - direction, at a medium vertex and at a surface: prepared once per vertex, then the density
//    NEE's MIS uses and the sampled continuation;
//  - continuation, at a medium vertex after the distance and after the direction decision: how many
//    copies of the path go on (guided RR and splitting, theory.md §9.3);
//  - recording: the medium vertices, their NEE samples and every contribution (training).
// The defaults are the analog decisions with exactly the random numbers the walk without a policy
// draws (free flight, phase and BSDF sampling, no continuation decision) and no recording: a policy
// overrides what it adds. A guiding backend is one policy class (guided_walk_policy.h for the
// guiding field's WalkGuide; training_recorder.h records). A policy object serves one walk at a
// time (it keeps the prepared samplers and scratch between the calls of one vertex): not shared
// between threads.
//
// What one decision hands to the next at the same vertex (the guiding structure's region of the
// vertex, which the distance decision finds and the direction and continuation decisions reuse)
// travels in a GuideRegion that the walk keeps with the vertex and clears when the path leaves it.
#include <limits>
#include <utility>

#include "volguide/core/sampler.h"
#include "volguide/media/medium.h"
#include "volguide/media/phase.h"
#include "volguide/render/bsdf.h"

namespace volguide {

// The region of the guiding structure the path's current vertex lies in (for the guiding field:
// its kd leaf), -1 when not known. Opaque to the walk: the policy fills and reads it.
struct GuideRegion {
    int leaf = -1;
};

enum class ContinuationStage {
    Distance,   // after the distance decision: the vertex collects L_i(x, w) from here on (w: the ray's direction)
    Direction,  // after the direction decision: the continuation along w collects L(x, w)
};

// A continuation decision: n copies of the path go on, each with the weight 1/q (E[n] = q).
struct Continuation {
    float q = 1.f;        // 1: no decision (n = 1, nothing drawn)
    int n = 1;
    bool guided = false;  // made from an estimate: it replaces throughput RR at this depth
};

class WalkPolicy {
  public:
    virtual ~WalkPolicy() = default;

    // Whether sample_distance departs from free flight (the walk's equiangular sampling, which
    // needs the distance density, is not combined with such a policy). `region` is the ray
    // origin's on entry, the scattering vertex's on return.
    virtual bool guides_distance() const { return false; }
    virtual FreeFlightSample sample_distance(const Medium& medium, const Ray& ray, float tmax,
                                             const Color3& throughput, Sampler& sampler, GuideRegion& region) {
        return medium.sample_free_flight(ray, tmax, throughput, sampler);
    }

    // The direction decision at the medium vertex mi (mi.medium set): prepare, then pdf and sample.
    // prepare may draw from `sampler` (Open PGL's stochastic region lookup); the defaults draw nothing.
    virtual void prepare_direction(const MediumInteraction& mi, GuideRegion& region, Sampler& sampler) {}
    virtual float direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const {
        return mi.medium->phase().pdf(mi.wi, wo);
    }
    virtual PhaseSample sample_direction(const MediumInteraction& mi, Sampler& sampler) {
        return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    }

    // The direction decision at a surface vertex (`medium`: the one the path arrived through):
    // prepare, then pdf (of a local direction) and sample (u1, u2 drawn by the walk).
    virtual void prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                                           Sampler& sampler) {}
    virtual float surface_direction_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const BSDF& bsdf,
                                        const Vec3f& wo_local) const {
        return bsdf.pdf(ctx, si, wo_local);
    }
    virtual std::pair<BSDFSample, Color3> sample_surface_direction(const BSDFContext& ctx, const SurfaceInteraction& si,
                                                                   const BSDF& bsdf, float u1, Point2f u2,
                                                                   Sampler& sampler) {
        return bsdf.sample(ctx, si, u1, u2);
    }

    // The continuation decision at the medium vertex mi of a path of weight `throughput` (w: see
    // ContinuationStage), when the camera sample has `branches` branches so far and this branch
    // the allowance `allowance` (see branch_budget): n must not exceed floor(allowance).
    virtual Continuation continuation(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                      const Color3& throughput, int branches, float allowance, Sampler& sampler,
                                      GuideRegion& region) {
        return {};
    }
    // A camera sample's branch allowance: the walk gives each of a split's n copies 1/n of their
    // path's (roulette_splitting.h). +inf: no budget.
    virtual float branch_budget() const { return std::numeric_limits<float>::infinity(); }
    // The camera sample ended with `branches` branches.
    virtual void end_camera_sample(int branches) {}

    // A copy of the path made by a continuation decision waits and is walked after the current
    // branch ended: branch_point() is called when it is made, resume_branch(its value) before it is
    // walked, so that a recorder credits what the copy collects to the vertices before the split.
    virtual int branch_point() { return 0; }
    virtual void resume_branch(int point) {}

    // Recording, in path order: a contribution added to the estimate (after throughput and MIS
    // weight); a medium vertex x after its direction w was sampled with density pdf (throughput
    // includes f_p / pdf); the MIS-weighted NEE estimate at x towards the light d; the surface
    // events below.
    virtual void record_contribution(const Color3& value) {}
    virtual void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) {}
    virtual void record_medium_nee(const Point3f& x, const Vec3f& d, const Color3& weight) {}
    // The ray reached the pending intersection si (invalid: it left the scene), before its
    // emission is added; and, at a surface, the BSDF's direction bs was sampled (wo: world
    // space; throughput includes its weight). Path-segment recorders (Open PGL) need both.
    virtual void record_surface_hit(const SurfaceInteraction& si) {}
    virtual void record_surface_vertex(const SurfaceInteraction& si, const BSDFSample& bs, const Vec3f& wo,
                                       const Color3& throughput) {}
};

}  // namespace volguide
