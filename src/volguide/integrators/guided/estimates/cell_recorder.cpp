#include "volguide/integrators/guided/estimates/cell_recorder.h"

#include <algorithm>

namespace volguide {

void CellRecorder::begin(long pixel, float estimate) {
    pixel_ = pixel;
    estimate_ = estimate > 0.f ? estimate : 1.f;
    nodes_.clear();
    branches_.clear();
    current_ = -1;
    total_ = 0.0;
    cost_ = unrecorded_ = 0;
    camera_branches_ = 1;
}

void CellRecorder::push(const Node& node) {
    nodes_.push_back(node);
    current_ = int(nodes_.size()) - 1;
}

void CellRecorder::record_contribution(const Color3& value) {
    const double v = double(value.average());
    total_ += v;
    if (current_ >= 0) nodes_[size_t(current_)].collected += v;
}

void CellRecorder::record_decision(DecisionKind kind, const DecisionRecord& record) {
    ++cost_;
    if (record.mixture)
        push({current_, true, uint8_t(kind), cell(record.leaf), 0, record.pdf, record.p_u, record.p_g, 0.0});
    else
        ++unrecorded_;
    if (current_ >= 0) ++nodes_[size_t(current_)].cost;
}

void CellRecorder::record_continuation(ContinuationStage stage, int leaf, const Vec3f& w, float,
                                       const Color3& throughput) {
    push({current_, false, uint8_t(stage), cell(leaf), continuation_direction_bin(w), 0.f, 0.f, 0.f,
          double(throughput.average())});
}

// A copy of the current node (the walk makes copies right after a continuation point's decision): a
// sibling with the same weight, walked later.
int CellRecorder::branch_point() {
    int copy = -1;
    if (current_ >= 0) {
        Node n = nodes_[size_t(current_)];
        n.collected = 0.0;
        n.cost = 0;
        nodes_.push_back(n);
        copy = int(nodes_.size()) - 1;
    }
    branches_.push_back(copy);
    return int(branches_.size()) - 1;
}

void CellRecorder::resume_branch(int point) { current_ = branches_[size_t(point)]; }

void CellRecorder::end() {
    // Parents precede their children: one backward sweep sums every subtree.
    for (size_t k = nodes_.size(); k-- > 0;) {
        const Node& n = nodes_[k];
        if (n.parent < 0) continue;
        nodes_[size_t(n.parent)].collected += n.collected;
        nodes_[size_t(n.parent)].cost += n.cost;
    }
    const double I = double(estimate_);
    for (const Node& n : nodes_) {
        if (n.decision) {
            const double s = std::max(0.0, n.collected) / I;  // clamped: float rounding of a sum of terms >= 0
            stats_.add_decision(DecisionKind(n.kind), n.cell, s * s, n.q, n.p_u, n.p_g);
        } else if (n.beta > 0.0) {
            stats_.add_continuation(ContinuationStage(n.kind), n.cell, n.bin, n.collected / n.beta, n.cost);
        }
    }
    const double x = total_ / I;
    stats_.add_camera_sample(x * x, cost_, unrecorded_, camera_branches_);
    pixels_.add(pixel_, x);
}

}  // namespace volguide
