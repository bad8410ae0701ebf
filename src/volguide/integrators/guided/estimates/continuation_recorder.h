#pragma once
// The recorder of rrs=ears (continuation_stats.h, docs/theory.md §9.8): follows one camera sample of the
// render's guided walk (a PathRecorder of volpath's walk, path_recorder.h) and, at its end, adds to the
// thread's ContinuationStatistics what every continuation point collected and cost, and the camera
// sample's relative value X / I to the film's PixelMoments.
//
// A continuation point is recorded after its decision (its weight beta includes 1/q); the copies a
// split makes are its siblings with the same beta (branch_point() makes one per copy, resume_branch()
// walks it), so each copy is one sample of the continuation: y = (what its subtree contributed) / beta,
// its cost the path events (medium and surface hits) in its subtree. A point killed by roulette records
// nothing: the survivors are an unbiased sample of the continuations, since survival does not depend on
// what the path would have collected.
//
// It wraps another recorder (`inner`, may be null: online learning's TrainingRecorder) and forwards every
// event to it, so that one walk feeds both.
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "volguide/integrators/guided/estimates/continuation_stats.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class ContinuationRecorder final : public PathRecorder {
  public:
    ContinuationRecorder(ContinuationStatistics& stats, PixelMoments& pixels) : stats_(stats), pixels_(pixels) {}

    // A new camera sample of the film's pixel `pixel` (-1: none) of estimate `estimate` (> 0).
    void begin(PathRecorder* inner, long pixel, float estimate);
    // Adds the camera sample's terms to the statistics.
    void end();

    void record_contribution(const Color3& value) override;
    void record_medium_hit(const MediumInteraction& mi) override;
    void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) override {
        if (inner_) inner_->record_medium_vertex(x, w, pdf, throughput);
    }
    void record_medium_nee(const Point3f& x, const Vec3f& d, const Color3& weight) override {
        if (inner_) inner_->record_medium_nee(x, d, weight);
    }
    void record_surface_hit(const SurfaceInteraction& si) override;
    void record_surface_vertex(const SurfaceInteraction& si, const BSDFSample& bs, const Vec3f& wo,
                               const Color3& throughput) override {
        if (inner_) inner_->record_surface_vertex(si, bs, wo, throughput);
    }
    bool records_decisions() const override { return inner_ && inner_->records_decisions(); }
    void record_decision(DecisionKind kind, const DecisionRecord& record) override {
        if (inner_) inner_->record_decision(kind, record);
    }
    void record_continuation(ContinuationStage stage, const VertexLeaf& vertex_leaf, const Vec3f& w, float estimate,
                             const Color3& throughput) override;
    int branch_point() override;
    void resume_branch(int point) override;
    void end_camera_sample(int branches) override;

  private:
    struct Point {
        int parent;  // -1: the camera sample's root
        ContinuationStage stage;
        size_t cell;
        int bin;
        double beta;
        double collected = 0.0;  // contributions while this point was the current one
        uint64_t events = 0;     // medium and surface hits while it was
    };
    struct Branch {
        int point;  // the copy's own point
        int inner;  // the inner recorder's branch point
    };
    size_t cell(int leaf) const {
        return leaf >= 0 && size_t(leaf) + 1 < stats_.cells() ? size_t(leaf) : stats_.cells() - 1;
    }
    void count_event() {
        ++events_;
        if (current_ >= 0) ++points_[size_t(current_)].events;
    }
    ContinuationStatistics& stats_;
    PixelMoments& pixels_;
    PathRecorder* inner_ = nullptr;
    long pixel_ = -1;
    float estimate_ = 1.f;
    std::vector<Point> points_;
    std::vector<Branch> branches_;
    int current_ = -1;
    double total_ = 0.0;
    uint64_t events_ = 0;
    int camera_branches_ = 1;
};

// rrs=ears's learning over a render: each thread's recorder and statistics of the current pass, the
// sums of the passes so far, the film's pixel moments and the snapshot the current pass decides with.
// end_pass() (between passes: no walk runs) adds the pass's sums and freezes the next snapshot.
class ContinuationLearning {
  public:
    // `cells`: the field's leaves + 1; the film's width and height.
    ContinuationLearning(size_t cells, int width, int height, const EarsSettings& settings);
    const ContinuationSnapshot& snapshot() const { return snapshot_; }
    // The calling thread's recorder (one camera sample at a time: begin ... end).
    ContinuationRecorder& recorder() const { return threads_.local().recorder; }
    long pixel(Point2f film_uv) const { return pixels_.pixel(film_uv); }
    // After a pass.
    void end_pass();
    // The snapshot's figures for --stats.
    std::vector<std::pair<std::string, double>> named() const;

  private:
    struct Thread {
        Thread(size_t cells, PixelMoments* pixels) : stats(cells), recorder(stats, *pixels) {}
        ContinuationStatistics stats;
        ContinuationRecorder recorder;
    };
    EarsSettings settings_;
    PixelMoments pixels_;
    mutable tbb::enumerable_thread_specific<Thread> threads_;
    ContinuationStatistics total_;
    ContinuationSnapshot snapshot_;
    double unsplit_cost_ = 0.0;  // C_0: the first pass's cost per camera sample
    int updates_ = 0;
    uint64_t recorded_ = 0;  // camera samples recorded so far
};

}  // namespace volguide
