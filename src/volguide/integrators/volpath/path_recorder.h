#pragma once
// What volpath's walk (volpath_walk.h) reports of one camera sample, apart from its decisions
// (walk_policy.h): the path's events in path order, for whoever learns from them. Two recorders
// plug in here: guided_volpath's learner (guided/estimates/cell_recorder.h: the learned selection's
// pilot and rrs=ears) and Open PGL's path segments (openpgl/openpgl_path_recorder.h). A recorder decides nothing: the walk draws the same random
// numbers with or without one. The defaults record nothing; a recorder overrides what it keeps.
// One recorder serves one walk at a time.
#include "volguide/core/color.h"
#include "volguide/geometry/interaction.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/render/bsdf.h"

namespace volguide {

class PathRecorder {
  public:
    virtual ~PathRecorder() = default;

    // A contribution added to the estimate (after throughput and MIS weight).
    virtual void record_contribution(const Color3& value) {}

    // The path reached the medium vertex mi (before its NEE and direction decision).
    virtual void record_medium_hit(const MediumInteraction& mi) {}
    // The medium vertex x after its direction w was sampled with density pdf (throughput includes
    // f_p / pdf).
    virtual void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) {}
    // The MIS-weighted NEE estimate at the medium vertex x towards the light d.
    virtual void record_medium_nee(const Point3f& x, const Vec3f& d, const Color3& weight) {}

    // The ray reached the pending intersection si (invalid: it left the scene), before its
    // emission is added; and, at a surface, the BSDF's direction bs was sampled (wo: world space;
    // throughput includes its weight). Path-segment recorders (Open PGL) need both.
    virtual void record_surface_hit(const SurfaceInteraction& si) {}
    virtual void record_surface_vertex(const SurfaceInteraction& si, const BSDFSample& bs, const Vec3f& wo,
                                       const Color3& throughput) {}

    // Whether the recorder reads the policy's decisions (record_decision, record_continuation):
    // the walk asks the policy for their densities and estimates only then.
    virtual bool records_decisions() const { return false; }
    // A distance or direction decision the policy made (`record`: what it sampled from).
    virtual void record_decision(DecisionKind kind, const DecisionRecord& record) {}
    // A continuation point of `stage` (w: see ContinuationStage) after its decision `c`, when the path
    // goes on: c.leaf the point's leaf in the guiding structure (-1: not known), c.estimate the field's
    // estimate of what the path collects from there per unit weight (channel average; 0 when the
    // policy did not report one, records_decisions()), c.q its factor, and the path weight (its 1/q
    // included). Reported at every continuation point of a walk with a policy, before the decision's
    // copies are made (branch_point). Surface-stage points report no estimate (0).
    virtual void record_continuation(ContinuationStage stage, const Continuation& c, const Vec3f& w,
                                     const Color3& throughput) {}

    // A copy of the path made by a continuation decision waits and is walked after the current
    // branch ended: branch_point() is called when it is made, resume_branch(its value) before it is
    // walked, so that a recorder credits what the copy collects to the vertices before the split.
    virtual int branch_point() { return 0; }
    virtual void resume_branch(int point) {}

    // The camera sample ended with `branches` branches.
    virtual void end_camera_sample(int branches) {}

    // The walk's work since the last report (work.h), outside the sampling decisions' own (which come
    // with their records): reported before every decision, continuation point, branch point, resumed
    // branch and the camera sample's end, so a recorder can credit it to what is current.
    virtual void record_work(const WorkCounts& work) {}
};

}  // namespace volguide
