#pragma once
// The one recorder of guided_volpath's learning (cell_statistics.h): follows one camera sample of the
// guided walk (a PathRecorder of volpath's walk, path_recorder.h) and, at its end, adds to the thread's
// CellStatistics what every guidable decision and continuation point was followed by, and the camera
// sample's relative value X / I to the film's PixelMoments.
//
// The camera sample's path tree: every decision a guide could make (drawn from a guided mixture, or
// unguided where the allocation's share is 0) and every continuation point is a node, a child of the
// node that was current when it was made; the contributions and the work reported while a node is
// current are its own, and what followed a node is the sum over its subtree. Costs are the cost
// model's (cost_model.h): a decision's own work (DecisionRecord::own) is its own cost, apart from what
// followed it. A continuation point is recorded after its decision (its weight beta includes 1/q);
// the copies a split makes are its siblings with the same beta and the same point (branch_point()
// makes one per copy, resume_branch() walks it), so each copy is one sample Y of the continuation:
// y = (what its subtree contributed) / beta, its cost the work in its subtree. A point killed by a
// decision's roulette records nothing: the survivors stand for it (cell_statistics.h). A point that
// made no decision is followed by the walk's own roulette (ContinuationQuery::roulette), whose
// weight is in what its copy collected.
#include <cstdint>
#include <vector>

#include "volguide/integrators/guided/estimates/cell_statistics.h"
#include "volguide/integrators/guided/estimates/cost_model.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class CellRecorder final : public PathRecorder {
  public:
    // All three must outlive the recorder.
    CellRecorder(CellStatistics& stats, PixelMoments& pixels, const CostModel& costs)
        : stats_(stats), pixels_(pixels), costs_(costs) {}

    // A new camera sample of the film's pixel `pixel` (-1: none) of estimate I (> 0; else 1); a
    // `control` sample (the unguided walk's) adds only its value and cost (CellStatistics::add_control_sample).
    void begin(long pixel, float estimate, bool control = false);
    // Adds the camera sample's terms to the statistics.
    void end();

    void record_contribution(const Color3& value) override;
    bool records_decisions() const override { return true; }
    void record_work(const WorkCounts& work) override;
    // A decision in the cell of record.leaf; one the guide could not make (record.guidable false) only
    // costs.
    void record_decision(DecisionKind kind, const DecisionRecord& record) override;
    void record_continuation(ContinuationStage stage, const Continuation& c, const Vec3f& w,
                             const Color3& throughput) override;
    int branch_point() override;
    void resume_branch(int point) override;
    void end_camera_sample(int branches) override { camera_branches_ = branches; }

  private:
    struct Node {
        int parent;  // -1: the camera sample's root
        bool decision;
        uint8_t kind;   // DecisionKind, or ContinuationStage
        size_t cell;
        // decision: the mixture (or not) and its densities at the sample, its own costs
        bool mixture = false;
        float q = 0.f, p_u = 0.f, p_g = 0.f;
        double own = 0.0, own_unguided = 0.0;
        // continuation: the point (copies share it), the path weight after the decision, the factors
        int point = -1, bin = 0;
        double beta = 0.0;
        float q_cur = 1.f, q_unguided = 1.f, q_guided = 1.f;
        bool decided = false, guided_known = false;
        double collected = 0.0;  // contributions while this node was the current one (then: its subtree's)
        double cost = 0.0;       // work while it was, and its children's own (then: everything after it)
    };
    size_t cell(int leaf) const {
        return leaf >= 0 && size_t(leaf) + 1 < stats_.cells() ? size_t(leaf) : stats_.cells() - 1;
    }
    void push(const Node& node);
    void add_cost(double c);
    // end()'s parts: the decisions' samples, and the continuation points' (grouped by point).
    void add_decisions() const;
    void add_points() const;

    CellStatistics& stats_;
    PixelMoments& pixels_;
    const CostModel& costs_;
    long pixel_ = -1;
    float estimate_ = 1.f;
    bool control_ = false;
    std::vector<Node> nodes_;
    std::vector<int> branches_;  // per branch point: the copy's node (-1: none)
    int current_ = -1;
    int points_ = 0;
    double total_ = 0.0, cost_ = 0.0;
    SampleOverhead overhead_;
    int camera_branches_ = 1;
};

}  // namespace volguide
