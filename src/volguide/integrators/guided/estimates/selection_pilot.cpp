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
    decisions_ = 0;
    pending_.clear();
}

static_assert(int(DecisionKind::Distance) == int(SelectionDecision::Distance) &&
              int(DecisionKind::Direction) == int(SelectionDecision::Direction) &&
              int(DecisionKind::Surface) == int(SelectionDecision::Surface));

void SelectionRecorder::record_decision(DecisionKind kind, const DecisionRecord& record) {
    ++decisions_;
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

void SelectionRecorder::end() {
    for (const Pending& p : pending_) {
        // Contributions are added in path order, so what followed p is the total since it
        // (clamped: float rounding of a sum of non-negative terms).
        const double S = std::max(0.0, total_ - p.before);
        if (p.is_method) {
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
    decisions_ = 0;
    unrecorded_ = 0;
    pending_.clear();
}

SelectionStatistics run_selection_pilot(
    const Scene& scene, int spp, size_t cells, const std::function<float(Point2f)>& pixel,
    const std::function<Color3(Sampler&, const Ray&, SelectionRecorder&)>& walk, const PreprocessContext& context,
    int method_round) {
    const Sensor& sensor = scene.sensor();
    const int W = sensor.film().width(), H = sensor.film().height();
    tbb::enumerable_thread_specific<SelectionStatistics> stats([&] { return SelectionStatistics(cells); });
    parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        SelectionStatistics& local = stats.local();
        SelectionRecorder recorder(local, cells);
        recorder.set_method_round(method_round);
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
