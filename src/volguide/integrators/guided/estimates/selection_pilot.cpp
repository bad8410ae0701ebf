#include "volguide/integrators/guided/estimates/selection_pilot.h"

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {
constexpr uint64_t kSelectionPilotStream = 0x5E1EC7ull;
}

void run_selection_pilot(const Scene& scene, int spp, const std::function<float(Point2f)>& pixel,
                         const std::function<Color3(Sampler&, const Ray&, CellRecorder&)>& walk,
                         const PreprocessContext& context, Learner& learner) {
    const Sensor& sensor = scene.sensor();
    const int W = sensor.film().width(), H = sensor.film().height();
    parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        CellRecorder& recorder = learner.recorder();
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (context.cancelled()) return;
            for (int x = 0; x < W; ++x)
                for (int k = 0; k < spp; ++k) {
                    Sampler sampler(context.seed, uint64_t(y) * uint64_t(W) + uint64_t(x), uint64_t(k),
                                    kSelectionPilotStream);
                    const Point2f pos = film_position(x, y, sampler.next_2d());
                    const Point2f film_uv(pos.x / float(W), pos.y / float(H));
                    recorder.begin(learner.pixel(film_uv), pixel(film_uv));
                    camera_sample_value(sensor, film_uv,
                                        [&](const CameraRay& camera) { return walk(sampler, camera.ray, recorder); });
                    recorder.end();
                }
        }
    });
    learner.end_pass();
}

}  // namespace volguide
