#include "volguide/integrators/guided/estimates/cell_recorder.h"

#include <algorithm>
#include <cmath>

namespace volguide {

void CellRecorder::begin(long pixel, float estimate, bool control) {
    pixel_ = pixel;
    control_ = control;
    estimate_ = estimate > 0.f ? estimate : 1.f;
    nodes_.clear();
    branches_.clear();
    current_ = -1;
    points_ = 0;
    total_ = cost_ = 0.0;
    overhead_ = {};
    camera_branches_ = 1;
}

void CellRecorder::push(const Node& node) {
    nodes_.push_back(node);
    current_ = int(nodes_.size()) - 1;
}

void CellRecorder::add_cost(double c) {
    cost_ += c;
    if (current_ >= 0) nodes_[size_t(current_)].cost += c;
}

void CellRecorder::record_contribution(const Color3& value) {
    const double v = double(value.average());
    total_ += v;
    if (current_ >= 0) nodes_[size_t(current_)].collected += v;
}

void CellRecorder::record_work(const WorkCounts& work) {
    add_cost(costs_.cost(work));
    overhead_.recording += costs_.ns(Work::Recorded) * double(work[Work::Recorded]);
    overhead_.policy += costs_.ns(Work::Policy) * double(work[Work::Policy]);
}

void CellRecorder::record_decision(DecisionKind kind, const DecisionRecord& record) {
    const double own = costs_.cost(record.own);
    add_cost(own);  // what followed the current node includes this decision
    if (!record.guidable && !record.mixture) return;
    Node n{current_, true, uint8_t(kind), cell(record.leaf)};
    n.mixture = record.mixture;
    n.q = record.pdf;
    n.p_u = record.p_u;
    n.p_g = record.p_g;
    n.own = own;
    n.own_unguided = costs_.unguided_cost(record.own);
    push(n);
}

void CellRecorder::record_continuation(ContinuationStage stage, const Continuation& c, const Vec3f& w,
                                       const Color3& throughput) {
    Node n{current_, false, uint8_t(stage), cell(c.leaf)};
    n.point = points_++;
    n.bin = continuation_direction_bin(w);
    n.beta = double(throughput.average());
    n.decided = c.guided || c.q != 1.f;
    n.q_cur = c.q;
    n.q_unguided = c.q_unguided;
    n.guided_known = !std::isnan(c.q_guided);
    n.q_guided = n.guided_known ? c.q_guided : 1.f;
    push(n);
}

// A copy of the current node (the walk makes copies right after a continuation point's decision): a
// sibling with the same weight and point, walked later.
int CellRecorder::branch_point() {
    int copy = -1;
    if (current_ >= 0) {
        Node n = nodes_[size_t(current_)];
        n.collected = 0.0;
        n.cost = 0.0;
        nodes_.push_back(n);
        copy = int(nodes_.size()) - 1;
    }
    branches_.push_back(copy);
    return int(branches_.size()) - 1;
}

void CellRecorder::resume_branch(int point) { current_ = branches_[size_t(point)]; }

void CellRecorder::add_decisions() const {
    const double I = double(estimate_);
    for (const Node& n : nodes_) {
        if (!n.decision) continue;
        const double s = std::max(0.0, n.collected) / I;  // clamped: float rounding of a sum of terms >= 0
        DecisionSample d;
        d.cell = n.cell;
        d.s2 = s * s;
        d.mixture = n.mixture;
        d.q_cur = n.q;
        d.p_u = n.p_u;
        d.p_g = n.p_g;
        d.own = n.own;
        d.own_unguided = n.own_unguided;
        d.after = n.cost;
        stats_.add_decision(DecisionKind(n.kind), d);
    }
}

// Each point's copies (nodes with its point id, in order of creation): their values y per unit weight
// give E[Y^2] and E[Y]^2 (from the products of distinct copies); ears reads each copy alone.
void CellRecorder::add_points() const {
    struct Point {
        int first = -1, n = 0;
        double sum = 0.0, sum_sq = 0.0, cost = 0.0;
    };
    std::vector<Point> points(static_cast<size_t>(points_));
    const double I = double(estimate_);
    for (size_t k = 0; k < nodes_.size(); ++k) {
        const Node& c = nodes_[k];
        if (c.decision || !(c.beta > 0.0)) continue;
        const double y = c.collected / c.beta;
        stats_.add_continuation(ContinuationStage(c.kind), c.cell, c.bin, y, c.cost);
        Point& p = points[size_t(c.point)];
        if (p.first < 0) p.first = int(k);
        ++p.n;
        p.sum += y;
        p.sum_sq += y * y;
        p.cost += c.cost;
    }
    for (const Point& p : points) {
        if (p.first < 0) continue;
        const Node& c = nodes_[size_t(p.first)];
        ContinuationSample s;
        s.cell = c.cell;
        s.q_unguided = c.q_unguided;
        s.q_guided = c.q_guided;
        s.guided_known = c.guided_known;
        const double n = double(p.n);
        s.a2 = p.sum_sq / n;
        s.b2 = p.n > 1 ? std::max(0.0, p.sum * p.sum - p.sum_sq) / (n * (n - 1.0)) : s.a2;
        s.copy_cost = p.cost / n;
        if (c.decided) {
            s.q_cur = c.q_cur;
            s.b = c.beta * double(c.q_cur) / I;
        } else {
            // No decision: the walk's roulette of survival q_u followed, its 1/q_u in what the copy
            // collected; every such point is recorded (the killed ones with nothing collected).
            const double q_u = std::max(double(c.q_unguided), 1e-6);
            s.q_cur = 1.f;
            s.a2 *= q_u;
            s.b2 = s.a2;
            s.copy_cost /= q_u;
            s.b = c.beta / I;
        }
        stats_.add_continuation_point(s);
    }
}

void CellRecorder::end() {
    if (control_) {
        const double x = total_ / double(estimate_);
        stats_.add_control_sample(x * x, cost_ - overhead_.recording - overhead_.policy);
        pixels_.add(pixel_, x);  // an unbiased sample of the pixel's mean like the others
        return;
    }
    // Parents precede their children: one backward sweep sums every subtree.
    for (size_t k = nodes_.size(); k-- > 0;) {
        const Node& n = nodes_[k];
        if (n.parent < 0) continue;
        nodes_[size_t(n.parent)].collected += n.collected;
        nodes_[size_t(n.parent)].cost += n.cost;
    }
    add_decisions();
    add_points();
    const double x = total_ / double(estimate_);
    stats_.add_camera_sample(x * x, cost_, camera_branches_, overhead_);
    pixels_.add(pixel_, x);
}

}  // namespace volguide
