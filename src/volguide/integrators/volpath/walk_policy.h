#pragma once
// The decisions through which what guiding and guided RR/splitting add enters volpath's walk
// (volpath_walk.h). The walk asks its policy for every decision:
//  - distance: where along the ray in a medium the next real scattering happens (the contract of
//    Medium::sample_free_flight);
//  - direction, at a medium vertex and at a surface: prepared once per vertex, then the density
//    NEE's MIS uses and the sampled continuation;
//  - continuation, at a medium vertex after the distance and after the direction decision: how many
//    copies of the path go on (guided RR and splitting, docs/theory.md §9.3), within the camera sample's
//    branch budget; with a policy that asks for it, also after a diffuse direction at a surface (§9.8).
// What the walk reports of the path (training, Open PGL's path segments, the selection pilot) is a
// PathRecorder's (path_recorder.h), not the policy's: a walk takes one of each, either may be null.
// The defaults are the unguided decisions with exactly the random numbers the walk without a policy
// draws (free flight, phase and BSDF sampling, no continuation decision): a policy overrides what
// it adds. A guiding backend is one policy class (guided/walk/guided_walk_policy.h for the guiding
// field's WalkGuide, openpgl/openpgl_walk_policy.h). A policy object serves one walk at a time (it
// keeps the current vertex's prepared samplers and scratch between the calls of one vertex): not
// shared between threads.
//
// The medium vertex the decisions are made at is the policy's (Open PGL's Init / Sample / PDF shape):
// the walk tells it where a vertex begins (begin_vertex, after the distance decision that reached it
// and before every decision at it) and when the path's ray no longer leaves from one (end_vertex: the
// camera, a surface); the policy keeps one object for it that the distance-stage continuation, the
// direction decision, the direction-stage continuation and the next segment's distance decision
// read. What a distance decision found of the vertex it reached (the guiding structure's leaf) stays
// with the policy: the walk keeps no state of the policy's.
#include <cstdint>
#include <limits>
#include <utility>

#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/work.h"
#include "volguide/media/medium.h"
#include "volguide/media/phase.h"
#include "volguide/render/bsdf.h"

namespace volguide {

enum class ContinuationStage {
    Distance,   // after the distance decision: the vertex collects L_i(x, w) from here on (w: the ray's direction)
    Direction,  // after the direction decision: the continuation along w collects L(x, w)
    Surface,    // after the BSDF's diffuse direction at a surface vertex: the continuation along w collects L(x, w)
};

// A continuation decision: n copies of the path go on, each with the weight 1/q (E[n] = q).
struct Continuation {
    float q = 1.f;        // 1: no decision (n = 1, nothing drawn)
    int n = 1;
    bool guided = false;  // made from an estimate: it replaces throughput RR at this depth
    // The estimate of what the path collects from here on per unit weight that the decision read
    // (channel average), when asked to report it; 0: none (for the recorders, path_recorder.h).
    float estimate = 0.f;
    // The guiding structure's leaf of the point as the decision left it (for the recorders); -1: not known.
    int leaf = -1;
    // For the recorders (what a region's choice between the guided and the unguided continuation is
    // learned from): the factor the unguided continuation applies here (ContinuationQuery::roulette)
    // and the one the guided rule gives (NaN: not computed here).
    float q_unguided = 1.f;
    float q_guided = std::numeric_limits<float>::quiet_NaN();
};

// The sampling decisions (also the learned selection's: its tables are indexed by them).
enum class DecisionKind : uint8_t { Distance = 0, Direction = 1, Surface = 2 };

// What a distance decision is asked: the segment (0, tmax) of `ray` in `medium` (the contract of
// Medium::sample_free_flight), the path weight (its channel shares split the decision over the colour
// channels, docs/theory.md §2.6) and the walk's depth: the real scattering events before the segment
// (0: the camera ray's, null surfaces crossed).
struct DistanceQuery {
    const Medium& medium;
    const Ray& ray;
    float tmax;
    Color3 throughput;
    int depth = 0;
};

// What a continuation decision is asked (see WalkPolicy::continuation): the stage, the direction w
// the continuation collects along (see ContinuationStage), the path weight, the camera sample's
// branches so far and this branch's allowance (n must not exceed floor(allowance), see branch_budget),
// and whether to report the estimate (Continuation::estimate) also where no decision is made.
struct ContinuationQuery {
    ContinuationStage stage = ContinuationStage::Distance;
    Vec3f w;
    Color3 throughput;
    int branches = 1;
    float allowance = std::numeric_limits<float>::infinity();
    bool report = false;
    // The walk's own throughput roulette at this point: the survival probability it applies after the
    // vertex's direction stage when no continuation decision replaces it (past rr_depth, once per
    // depth), 1 where it does not play (the distance stage, shallow depths).
    float roulette = 1.f;
    // min(1, max(beta) eta^2): the bounded rule's survival at this point, the floor of a guided roulette.
    float bound = 1.f;
};

// The surface vertex a surface direction decision is made at: the BSDF context, the interaction and
// its BSDF.
struct SurfaceQuery {
    const BSDFContext& ctx;
    const SurfaceInteraction& si;
    const BSDF& bsdf;
};

// What a sampling decision drew from, when the walk asks for it (for the recorders): a one-sample
// mixture of an unguided and a guided density whose parts are known, in the guiding structure's
// leaf `leaf` (-1: outside it); mixture false: a decision without such a mixture, made unguided —
// `guidable` says whether a guide could have made it (a share of 0 chose the unguided decision; a
// mixture is always guidable). `own`: the work of the decision itself (the walk fills it: its own
// units and the policy's since the last decision, work.h), apart from what followed it.
struct DecisionRecord {
    bool mixture = false;
    int leaf = -1;
    float pdf = 0.f, p_u = 0.f, p_g = 0.f;  // the mixture's density at the sample and its two parts
    bool guidable = false;
    WorkCounts own{};
};

class WalkPolicy {
  public:
    virtual ~WalkPolicy() = default;

    // Whether sample_distance departs from free flight (the walk's equiangular sampling, which
    // needs the distance density, is not combined with such a policy). The ray leaves from the
    // policy's current vertex (begin_vertex; none after end_vertex). The sampling decisions fill
    // `record` when it is not null (the defaults leave it a decision without a mixture).
    virtual bool guides_distance() const { return false; }
    virtual FreeFlightSample sample_distance(const DistanceQuery& query, Sampler& sampler, DecisionRecord* record) {
        return query.medium.sample_free_flight(query.ray, query.tmax, query.throughput, sampler);
    }

    // A real scattering event at mi (mi.medium set): the decisions that follow, up to and including
    // the distance decision of the segment leaving it, are this vertex's. When the last distance
    // decision reached it, what that decision found of it is the policy's own (the walk hands nothing
    // on); a vertex the walk reached otherwise (equiangular sampling) follows no distance decision of
    // the policy's. The default keeps nothing.
    virtual void begin_vertex(const MediumInteraction& mi) {}
    // The path's ray leaves from no medium vertex (the camera, a surface): the next distance decision
    // has no origin vertex.
    virtual void end_vertex() {}
    // The walk splits the path at the current vertex: the policy may keep what it found there for the
    // copies (a token the walk stores with them; -1: nothing kept, the default).
    virtual int keep_vertex() { return -1; }
    // A copy resumes from the vertex mi it was made at, with keep_vertex's token: the policy's vertex
    // is that one again, nothing found twice. The default begins it anew.
    virtual void resume_vertex(const MediumInteraction& mi, int kept) { begin_vertex(mi); }

    // The direction decision at the current medium vertex mi (mi.medium set): prepare, then pdf and
    // sample. prepare may draw from `sampler` (Open PGL's stochastic lookup of its own regions); the
    // defaults draw nothing.
    virtual void prepare_direction(const MediumInteraction& mi, Sampler& sampler) {}
    virtual float direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const {
        return mi.medium->phase().pdf(mi.wi, wo);
    }
    virtual PhaseSample sample_direction(const MediumInteraction& mi, Sampler& sampler, DecisionRecord* record) {
        return mi.medium->phase().sample(mi.wi, sampler.next_2d());
    }

    // The direction decision at a surface vertex (`medium`: the one the path arrived through):
    // prepare, then pdf (of a local direction) and sample (u1, u2 drawn by the walk).
    virtual void prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                                           Sampler& sampler) {}
    virtual float surface_direction_pdf(const SurfaceQuery& at, const Vec3f& wo_local) const {
        return at.bsdf.pdf(at.ctx, at.si, wo_local);
    }
    virtual std::pair<BSDFSample, Color3> sample_surface_direction(const SurfaceQuery& at, float u1, Point2f u2,
                                                                   Sampler& sampler, DecisionRecord* record) {
        return at.bsdf.sample(at.ctx, at.si, u1, u2);
    }

    // The continuation decision of `query` at the current medium vertex mi.
    virtual Continuation continuation(const ContinuationQuery& query, const MediumInteraction& mi, Sampler& sampler) {
        return {};
    }
    // The continuation decision at the surface vertex si after its BSDF sampled the diffuse direction
    // query.w (stage Surface; asked only when decides_at_surfaces()); the leaf the decision used in
    // Continuation::leaf.
    virtual bool decides_at_surfaces() const { return false; }
    virtual Continuation surface_continuation(const SurfaceInteraction& si, const ContinuationQuery& query,
                                              Sampler& sampler) {
        return {};
    }
    // A camera sample's branch allowance: the walk gives each of a split's n copies 1/n of their
    // path's (roulette_splitting.h). +inf: no budget.
    virtual float branch_budget() const { return std::numeric_limits<float>::infinity(); }
    // The camera sample ended with `branches` branches (the continuation decisions' statistics).
    virtual void end_camera_sample(int branches) {}
    // The work of the policy's guided decisions since the last call (work.h), handed to the walk and
    // reset: the walk asks after each sampling decision (the decision's own work) and before each
    // event it reports. The defaults count nothing.
    virtual WorkCounts take_work() { return {}; }
};

}  // namespace volguide
