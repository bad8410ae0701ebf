#include "volguide/integrators/guided/estimates/continuation_recorder.h"

#include <cmath>

#include "volguide/core/sampler.h"  // mix64

namespace volguide {

void ContinuationRecorder::begin(PathRecorder* inner, long pixel, float estimate) {
    inner_ = inner;
    pixel_ = pixel;
    estimate_ = estimate > 0.f ? estimate : 1.f;
    points_.clear();
    branches_.clear();
    current_ = -1;
    total_ = 0.0;
    events_ = 0;
    camera_branches_ = 1;
}

void ContinuationRecorder::record_contribution(const Color3& value) {
    const double v = double(value.average());
    total_ += v;
    if (current_ >= 0) points_[size_t(current_)].collected += v;
    if (inner_) inner_->record_contribution(value);
}

void ContinuationRecorder::record_medium_hit(const MediumInteraction& mi) {
    count_event();
    if (inner_) inner_->record_medium_hit(mi);
}

void ContinuationRecorder::record_surface_hit(const SurfaceInteraction& si) {
    count_event();
    if (inner_) inner_->record_surface_hit(si);
}

void ContinuationRecorder::record_continuation(ContinuationStage stage, const VertexLeaf& vertex_leaf,
                                               const Vec3f& w, float estimate, const Color3& throughput) {
    points_.push_back({current_, stage, cell(vertex_leaf.leaf), continuation_direction_bin(w),
                       double(throughput.average())});
    current_ = int(points_.size()) - 1;
    if (inner_) inner_->record_continuation(stage, vertex_leaf, w, estimate, throughput);
}

// A copy of the current point (the walk makes copies right after the point's decision): a sibling
// with the same weight, walked later.
int ContinuationRecorder::branch_point() {
    const int inner = inner_ ? inner_->branch_point() : 0;
    int copy = -1;
    if (current_ >= 0) {
        Point p = points_[size_t(current_)];
        p.collected = 0.0;
        p.events = 0;
        points_.push_back(p);
        copy = int(points_.size()) - 1;
    }
    branches_.push_back({copy, inner});
    return int(branches_.size()) - 1;
}

void ContinuationRecorder::resume_branch(int point) {
    const Branch& b = branches_[size_t(point)];
    current_ = b.point;
    if (inner_) inner_->resume_branch(b.inner);
}

void ContinuationRecorder::end_camera_sample(int branches) {
    camera_branches_ = branches;
    if (inner_) inner_->end_camera_sample(branches);
}

void ContinuationRecorder::end() {
    // Parents precede their children: one backward sweep sums every subtree.
    for (size_t k = points_.size(); k-- > 0;) {
        const Point& p = points_[k];
        if (p.parent < 0) continue;
        points_[size_t(p.parent)].collected += p.collected;
        points_[size_t(p.parent)].events += p.events;
    }
    for (const Point& p : points_)
        if (p.beta > 0.0) stats_.add_point(p.stage, p.cell, p.bin, p.collected / p.beta, p.events);
    stats_.add_camera_sample(events_, camera_branches_);
    pixels_.add(pixel_, total_ / double(estimate_));
    inner_ = nullptr;
}

ContinuationLearning::ContinuationLearning(size_t cells, int width, int height, const EarsSettings& settings)
    : settings_(settings), pixels_(width, height), threads_(cells, &pixels_), total_(cells) {
    snapshot_ = ContinuationSnapshot::from(total_, pixels_, settings_, 0.0);
}

void ContinuationLearning::end_pass() {
    // Integer sums: the order of the threads does not matter.
    for (Thread& t : threads_) {
        total_ += t.stats;
        t.stats.clear();
    }
    // The first pass decided nothing (no statistics yet): its cost is the unsplit walk's.
    if (updates_ == 0 && total_.camera_samples() > 0)
        unsplit_cost_ = double(total_.cost()) / double(total_.camera_samples());
    snapshot_ = ContinuationSnapshot::from(total_, pixels_, settings_, unsplit_cost_);
    recorded_ = total_.camera_samples();
    ++updates_;
}

std::vector<std::pair<std::string, double>> ContinuationLearning::named() const {
    return {{"ears_updates", double(updates_)},
            {"ears_learned_points", double(snapshot_.learned_points())},
            {"ears_learned_surface_points", double(snapshot_.learned_surface_points())},
            {"ears_image_relative_variance", snapshot_.image_variance()},
            {"ears_image_cost_per_sample", snapshot_.image_cost()},
            {"ears_branch_budget", double(snapshot_.branch_budget())},
            {"ears_unsplit_cost_per_sample", unsplit_cost_},
            {"ears_recorded_camera_samples", double(recorded_)}};
}

}  // namespace volguide
