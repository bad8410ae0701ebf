#pragma once
// The one recorder of guided_volpath's learning (cell_statistics.h): follows one camera sample of the
// guided walk (a PathRecorder of volpath's walk, path_recorder.h) and, at its end, adds to the thread's
// CellStatistics what every sampling decision and continuation point was followed by, and the camera
// sample's relative value X / I to the film's PixelMoments.
//
// The camera sample's path tree: every decision drawn from a guided mixture and every continuation
// point is a node, a child of the node that was current when it was made; the contributions and the
// decisions made while a node is current are its own, and what followed a node is the sum over its
// subtree. A continuation point is recorded after its decision (its weight beta includes 1/q); the
// copies a split makes are its siblings with the same beta (branch_point() makes one per copy,
// resume_branch() walks it), so each copy is one sample of the continuation: y = (what its subtree
// contributed) / beta, its cost the decisions in its subtree. A point killed by roulette records
// nothing: the survivors are an unbiased sample of the continuations, since survival does not depend on
// what the path would have collected. A decision's S is what its subtree contributed (the pilot walks
// without splitting: everything after it).
#include <cstdint>
#include <vector>

#include "volguide/integrators/guided/estimates/cell_statistics.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class CellRecorder final : public PathRecorder {
  public:
    // Both must outlive the recorder.
    CellRecorder(CellStatistics& stats, PixelMoments& pixels) : stats_(stats), pixels_(pixels) {}

    // A new camera sample of the film's pixel `pixel` (-1: none) of estimate I (> 0; else 1).
    void begin(long pixel, float estimate);
    // Adds the camera sample's terms to the statistics.
    void end();

    void record_contribution(const Color3& value) override;
    bool records_decisions() const override { return true; }
    // A decision in the cell of record.leaf sampled with density record.pdf from the mixture of the
    // unguided and guided densities p_u, p_g; one without a guided mixture only costs.
    void record_decision(DecisionKind kind, const DecisionRecord& record) override;
    void record_continuation(ContinuationStage stage, int leaf, const Vec3f& w, float estimate,
                             const Color3& throughput) override;
    int branch_point() override;
    void resume_branch(int point) override;
    void end_camera_sample(int branches) override { camera_branches_ = branches; }

  private:
    struct Node {
        int parent;  // -1: the camera sample's root
        bool decision;
        uint8_t kind;  // DecisionKind, or ContinuationStage
        size_t cell;
        int bin;                      // continuation: the direction bin
        float q, p_u, p_g;            // decision: the mixture's density and parts at the sample
        double beta;                  // continuation: the path weight after the decision
        double collected = 0.0;       // contributions while this node was the current one (then: its subtree's)
        uint64_t cost = 0;            // decisions while it was (then: its subtree's)
    };
    size_t cell(int leaf) const {
        return leaf >= 0 && size_t(leaf) + 1 < stats_.cells() ? size_t(leaf) : stats_.cells() - 1;
    }
    void push(const Node& node);

    CellStatistics& stats_;
    PixelMoments& pixels_;
    long pixel_ = -1;
    float estimate_ = 1.f;
    std::vector<Node> nodes_;
    std::vector<int> branches_;  // per branch point: the copy's node (-1: none)
    int current_ = -1;
    double total_ = 0.0;
    uint64_t cost_ = 0, unrecorded_ = 0;
    int camera_branches_ = 1;
};

}  // namespace volguide
