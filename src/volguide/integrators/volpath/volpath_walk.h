#pragma once
// volpath's walk of one camera sample (volpath.h gives the semantics): a small object over one
// WalkState, with the medium step (distance decision), the scattering at a medium vertex (NEE and
// direction), the surface step (emitter hit, NEE, BSDF sampling) as member functions. Guiding and
// guided RR/splitting enter through one WalkPolicy (walk_policy.h; null: the unguided walk), and what
// the walk reports of the path goes to one PathRecorder (path_recorder.h; null: nothing recorded).
// Split copies of the path (guided splitting) wait on the walk's own stack and draw from
// streams forked off the camera sample's; the first branch draws from the caller's sampler, so
// that without splitting the walk is volpath's number for number.
#include <limits>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/geometry/interaction.h"
#include "volguide/integrators/volpath/equiangular_mis.h"
#include "volguide/integrators/volpath/path_recorder.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/render/bsdf.h"

namespace volguide {

class Scene;

// The state a path carries from one event to the next (everything but the pending intersection):
// what a split copy inherits.
struct WalkState {
    Color3 throughput{1.f};
    float eta = 1.f;
    Ray ray;
    const Medium* medium = nullptr;
    int depth = 0;             // real scattering events so far (null crossings do not count)
    int rr_depth_done = -1;    // Russian roulette is played once per depth
    int null_crossings = 0;
    bool specular_chain = false;  // the last real event was a delta lobe: emitter hits count fully
    Interaction last_vertex;   // last real scattering vertex and the pdf of the direction it sampled
    float last_pdf = 1.f;
    EquiVertex last_equi;      // equiangular bookkeeping of the last medium vertex (MIS of hits)
    // The branches this path may still become (the policy's branch budget, shared by a split's copies).
    float split_allowance = std::numeric_limits<float>::infinity();
};

// A medium scattering vertex before its NEE and direction decision.
struct MediumVertex {
    MediumInteraction mi;
    EquiVertex equi;
};

class VolumeWalk {
  public:
    // scene, settings, sampler, policy and recorder (either may be null) must outlive the walk.
    VolumeWalk(const Scene& scene, const VolPathSettings& settings, Sampler& sampler, WalkPolicy* policy,
               PathRecorder* recorder = nullptr);
    // The camera sample's estimate along camera_ray: every branch's contributions.
    Color3 run(const Ray& camera_ray) { return run(camera_ray, nullptr, true); }
    // What the camera sample did (work.h), the policy's work included; complete after run().
    const WorkCounts& work() const { return work_; }
    // The same walk from a ray that starts inside `medium` (null: in vacuum) rather than at the
    // sensor: the radiance probes of radiance_probe.h.
    Color3 run_from(const Ray& ray, const Medium* medium) { return run(ray, medium, false); }

  private:
    Color3 run(const Ray& ray, const Medium* medium, bool from_sensor);
    // One branch of the camera sample waiting on the stack: its state, its own random stream,
    // and, for a copy made at a medium vertex, that vertex.
    struct PendingBranch {
        WalkState state;
        Sampler sampler;
        bool at_vertex = false;    // resume at `vertex`, else trace state.ray
        bool has_vertex = false;   // made at the medium vertex `vertex` (state.ray leaves from it)
        MediumVertex vertex;
        int record_point = 0;  // the recorder's branch_point() when the copy was made
        int kept = -1;         // the policy's keep_vertex() token for `vertex` (-1: nothing kept)
    };

    // One branch from the current state to its end.
    void walk_branch();
    // Throughput Russian roulette, once per depth from rr_depth on; false: the path ends.
    bool russian_roulette();
    enum class Step { Scatter, Surface, End };
    // The distance decision in the current medium up to the pending intersection.
    Step medium_step(MediumVertex& v);
    Step equiangular_step(const Medium& medium, float tmax, MediumVertex& v);
    // A real scattering event at v (reached by the state's ray): the distance-stage continuation
    // decision, then scatter(). False when the path ends there.
    bool at_medium_vertex(const MediumVertex& v);
    // NEE and the direction decision at v (and the direction-stage continuation decision).
    bool scatter(const MediumVertex& v);
    void sample_nee_medium(const MediumVertex& v);
    // The ray reached the pending intersection (or left the scene): emission, then at a surface NEE
    // and the BSDF's direction. False when the path ends there.
    bool surface_step();
    void emitter_hit();
    void sample_nee_surface(const BSDF& bsdf);
    // The policy's continuation decision at the medium vertex v, reported to the recorder, then
    // continue_copies().
    bool continue_path(ContinuationStage stage, const MediumVertex& v, const Vec3f& w);
    // The walk's part of a continuation decision c of `stage` (w: see ContinuationStage): the path's
    // weight 1/q, the point's report to the recorder, and its n - 1 copies; copies made at the
    // distance stage resume at `vertex` before its NEE and direction, the others trace the state's
    // ray (from `vertex` when not null: the policy's vertex again). False when the path ends.
    bool continue_copies(const Continuation& c, ContinuationStage stage, const Vec3f& w, const MediumVertex* vertex);
    // A branch taken from the stack: the policy's vertex is the one it was made at (with what the
    // policy kept of it), or none.
    void resume_policy_vertex(const PendingBranch& b);
    // The policy's continuation decision after a diffuse direction wo at the surface si_ (the state
    // already leaves along wo), then continue_copies(). False when the path ends.
    bool continue_at_surface(const Vec3f& wo);
    // What a continuation decision of `stage` along w is asked.
    ContinuationQuery continuation_query(ContinuationStage stage, const Vec3f& w) const;
    // The DecisionRecord a sampling decision fills (null unless the recorder reads them), and its report.
    DecisionRecord* decision_record(DecisionRecord& record) const { return records_decisions_ ? &record : nullptr; }
    void report_decision(DecisionKind kind, DecisionRecord& record);
    // Work: the walk's own units since the last report (count), the policy's after a decision it
    // made outside the sampling decisions (take_policy_work), and the report of what is pending to
    // the recorder (report_work: before every event it records, so the work is credited to what was
    // current while it was done).
    void count(Work unit, uint64_t n = 1) { pending_.add(unit, n); }
    void take_policy_work() {
        if (policy_) pending_ += policy_->take_work();
    }
    void report_work();
    // Every contribution goes through add(): the recorder records it.
    void add(const Color3& c);
    bool depth_ok(int d) const { return settings_.max_depth < 0 || d < settings_.max_depth; }


    const Scene& scene_;
    const VolPathSettings& settings_;
    WalkPolicy* policy_;
    PathRecorder* recorder_;
    const bool records_decisions_;  // a policy makes the decisions and the recorder reads them
    const bool guide_distance_;
    const BSDFContext ctx_;
    Sampler* rng_;             // the current branch's stream
    Sampler branch_sampler_;   // a split copy's stream
    WalkState state_;
    SurfaceInteraction si_;    // the pending intersection of state_.ray
    bool need_intersection_ = true;
    Color3 result_{0.f};
    int branches_ = 1;
    std::vector<PendingBranch> stack_;
    WorkCounts work_;     // the camera sample's, reported
    WorkCounts pending_;  // done since the last report
};

}  // namespace volguide
