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
    pending_.clear();
}

static_assert(int(DecisionKind::Distance) == int(SelectionDecision::Distance) &&
              int(DecisionKind::Direction) == int(SelectionDecision::Direction) &&
              int(DecisionKind::Surface) == int(SelectionDecision::Surface));

void SelectionRecorder::record_decision(DecisionKind kind, const DecisionRecord& record) {
    if (!record.mixture) {
        ++unrecorded_;
        return;
    }
    pending_.push_back({uint8_t(kind), cell(record.leaf), record.pdf, record.p_u, record.p_g, total_});
}

void SelectionRecorder::end() {
    for (const Pending& p : pending_) {
        // Contributions are added in path order, so what followed p is the total since it
        // (clamped: float rounding of a sum of non-negative terms).
        const double s = std::max(0.0, total_ - p.before) / double(pixel_);
        stats_.add_decision(SelectionDecision(p.kind), p.cell, s * s, p.q, p.p_u, p.p_g);
    }
    stats_.add_unrecorded_decisions(unrecorded_);
    const double x = total_ / double(pixel_);
    stats_.add_camera_sample(x * x);
    unrecorded_ = 0;
    pending_.clear();
}

SelectionStatistics run_selection_pilot(const Scene& scene, int spp, size_t cells,
                                        const std::function<float(Point2f)>& pixel,
                                        const std::function<Color3(Sampler&, const Ray&, SelectionRecorder&)>& walk,
                                        const PreprocessContext& context) {
    const Sensor& sensor = scene.sensor();
    const int W = sensor.film().width(), H = sensor.film().height();
    tbb::enumerable_thread_specific<SelectionStatistics> stats([&] { return SelectionStatistics(cells); });
    parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        SelectionStatistics& local = stats.local();
        SelectionRecorder recorder(local, cells);
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
