#include "volguide/integrators/guided/estimates/selection_pilot.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <optional>

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {
constexpr uint64_t kSelectionPilotStream = 0x5E1EC7ull;
}

void SelectionRecorder::begin(float pixel) {
    pixel_ = pixel > 0.f ? pixel : 1.f;
    total_ = 0.0;
    decisions_ = {};
    cost_ = 0.0;
    pending_.clear();
}

static_assert(int(DecisionKind::Distance) == int(SelectionDecision::Distance) &&
              int(DecisionKind::Direction) == int(SelectionDecision::Direction) &&
              int(DecisionKind::Surface) == int(SelectionDecision::Surface));

// The running counted cost of the camera sample, with the constants of method_cell_cost (selection.cpp).
void SelectionRecorder::count_cost(DecisionKind kind, const DecisionRecord& record) {
    const size_t m = size_t(method_);
    if (kind == DecisionKind::Distance) {
        cost_ += double(costs_.segment) + double(costs_.decision[m]);
        if (method_ == int(DistanceMethod::Bins) && record.lookups > 0)
            cost_ += double(costs_.bin_lookup) * double(record.lookups);
    } else if (kind == DecisionKind::Surface) {
        cost_ += double(costs_.segment) + (record.mixture ? double(costs_.guided_surface) : 0.0);
    } else if (record.mixture) {
        cost_ += double(costs_.guided_direction);
    }
}

void SelectionRecorder::record_decision(DecisionKind kind, const DecisionRecord& record) {
    ++decisions_[size_t(kind)];
    if (method_ >= 0) count_cost(kind, record);
    if (method_ >= 0 && kind != DecisionKind::Distance && record.mixture)  // the cost model's guided decisions
        stats_.add_method_event(DistanceMethod(method_), cell(record.leaf),
                                kind == DecisionKind::Direction ? CostEvent::GuidedDirection : CostEvent::GuidedSurface);
    if (method_ >= 0 && kind == DecisionKind::Distance && record.lookups >= 0) {
        Pending p;
        p.is_decision = false;
        p.is_method = true;
        p.cell = cell(record.leaf);
        p.lookups = uint32_t(record.lookups);
        p.before = total_;
        pending_.push_back(p);
    }
    if (!record.mixture) {
        ++unrecorded_;
        return;
    }
    Pending p;
    p.is_decision = true;
    p.kind = uint8_t(kind);
    p.cell = cell(record.leaf);
    p.q = record.pdf;
    p.p_u = record.p_u;
    p.p_g = record.p_g;
    p.before = total_;
    pending_.push_back(p);
}

void SelectionRecorder::record_continuation(ContinuationStage stage, const VertexLeaf& vertex_leaf, const Vec3f&,
                                            float estimate, const Color3& throughput) {
    const float beta = throughput.average();
    if (method_ >= 0) {
        stats_.add_method_event(DistanceMethod(method_), cell(vertex_leaf.leaf), CostEvent::Continuation);
        if (method_ != int(DistanceMethod::Volpath)) cost_ += double(costs_.estimate);
        if (splitting_ && beta > 0.f && estimate > 0.f) {
            // The render's q (eq. 9.1 from the channel averages, clamped; no branch cap): what
            // followed the point is paid q times instead of once (its roulette, q < 1, saves).
            const RouletteSplittingSettings& rs = *splitting_;
            const float r = beta * estimate / pixel_;
            float q = std::clamp(weight_window_factor(r, rs.window), rs.q_min, rs.q_max);
            if (rs.mode == RouletteMode::Guided) q = std::min(q, 1.f);
            if (q != 1.f) {
                Pending p;
                p.is_decision = false;
                p.is_method = true;
                p.kind = uint8_t(stage);
                p.cell = cell(vertex_leaf.leaf);
                p.split = q - 1.f;
                p.cost_before = cost_;
                pending_.push_back(p);
            }
        }
    }
    if (!(beta > 0.f) || !(estimate > 0.f)) return;
    Pending p;
    p.is_decision = false;
    p.kind = uint8_t(stage);
    p.cell = cell(vertex_leaf.leaf);
    p.estimate = estimate;
    p.beta = beta;
    p.before = total_;
    pending_.push_back(p);
}

// The render's branch cap: the copies charged to one camera sample (q - 1 summed over its
// splitting points) scaled down to at most max_branches - 1.
double SelectionRecorder::split_scale() const {
    if (!splitting_) return 1.0;
    double extra = 0.0;
    for (const Pending& p : pending_)
        if (p.is_method && p.split > 0.f) extra += double(p.split);
    const double cap = double(std::max(0, splitting_->max_branches - 1));
    return extra > cap ? cap / extra : 1.0;
}

void SelectionRecorder::end() {
    const double scale = split_scale();
    for (const Pending& p : pending_) {
        // Contributions are added in path order, so what followed p is the total since it
        // (clamped: float rounding of a sum of non-negative terms).
        const double S = std::max(0.0, total_ - p.before);
        if (p.is_method && p.split != 0.f) {
            const double copies = p.split > 0.f ? double(p.split) * scale : double(p.split);
            stats_.add_method_split_cost(DistanceMethod(method_), p.cell, copies * (cost_ - p.cost_before));
        } else if (p.is_method) {
            const double s = S / double(pixel_);
            stats_.add_method_decision(DistanceMethod(method_), p.cell, s * s, p.lookups);
        } else if (p.is_decision) {
            const double s = S / double(pixel_);
            stats_.add_decision(SelectionDecision(p.kind), p.cell, s * s, p.q, p.p_u, p.p_g);
        } else {
            stats_.add_continuation(int(p.kind), p.cell, double(p.estimate), S / double(p.beta));
        }
    }
    stats_.add_unrecorded_decisions(unrecorded_);
    const double x = total_ / double(pixel_);
    stats_.add_camera_sample(x * x);
    if (method_ >= 0) stats_.add_method_camera_sample(DistanceMethod(method_), x * x, decisions_);
    decisions_ = {};
    unrecorded_ = 0;
    pending_.clear();
}

SelectionStatistics run_selection_pilot(
    const Scene& scene, int spp, size_t cells, const std::function<float(Point2f)>& pixel,
    const std::function<Color3(Sampler&, const Ray&, SelectionRecorder&)>& walk, const PreprocessContext& context,
    int method_round, const SelectionCosts& costs, const RouletteSplittingSettings* splitting) {
    const Sensor& sensor = scene.sensor();
    const int W = sensor.film().width(), H = sensor.film().height();
    tbb::enumerable_thread_specific<SelectionStatistics> stats([&] { return SelectionStatistics(cells); });
    parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        SelectionStatistics& local = stats.local();
        SelectionRecorder recorder(local, cells);
        recorder.set_method_round(method_round);
        recorder.set_costs(costs, method_round == int(DistanceMethod::Volpath) ? nullptr : splitting);
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (context.cancelled()) return;
            for (int x = 0; x < W; ++x)
                for (int k = 0; k < spp; ++k) {
                    Sampler sampler(context.seed, uint64_t(y) * uint64_t(W) + uint64_t(x), uint64_t(k),
                                    kSelectionPilotStream);
                    const Point2f pos = film_position(x, y, sampler.next_2d());
                    const Point2f film_uv(pos.x / float(W), pos.y / float(H));
                    recorder.begin(pixel(film_uv));
                    camera_sample_value(sensor, film_uv,
                                        [&](const CameraRay& camera) { return walk(sampler, camera.ray, recorder); });
                    recorder.end();
                }
        }
    });
    SelectionStatistics total(cells);
    for (const SelectionStatistics& s : stats) total += s;  // integer sums: any order gives the same
    return total;
}

}  // namespace volguide
