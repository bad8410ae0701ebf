#include "volguide/integrators/guided/estimates/learning_pass.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {
constexpr uint64_t kLearningPassStream = 0x5E1EC7ull;

// The pilot pixels: blocks of b x b film pixels (b = 1: every pixel), one pixel drawn in each.
struct PilotBlocks {
    int b = 1, columns = 0, rows = 0;
};
PilotBlocks pilot_blocks(int W, int H) {
    PilotBlocks p;
    if (long(W) * long(H) > kPilotPixels)
        p.b = int(std::ceil(std::sqrt(double(W) * double(H) / double(kPilotPixels))));
    p.columns = (W + p.b - 1) / p.b;
    p.rows = (H + p.b - 1) / p.b;
    return p;
}
}  // namespace

uint64_t learning_pass_paths(int W, int H, int spp) {
    const PilotBlocks p = pilot_blocks(W, H);
    return uint64_t(p.columns) * uint64_t(p.rows) * uint64_t(std::max(0, spp));
}

uint64_t run_learning_pass(const Scene& scene, const LearningPassBudget& budget,
                           const std::function<float(Point2f)>& pixel,
                           const std::function<Color3(Sampler&, const CameraRay&, CellRecorder&)>& walk,
                           const PreprocessContext& context, Learner& learner) {
    const Sensor& sensor = scene.sensor();
    const int W = sensor.film().width(), H = sensor.film().height();
    const PilotBlocks blocks = pilot_blocks(W, H);
    const auto start = std::chrono::steady_clock::now();
    auto out_of_time = [&] {
        return budget.seconds > 0.0 &&
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > budget.seconds;
    };
    std::atomic<uint64_t> paths{0};
    parallel_for(tbb::blocked_range<int>(0, blocks.rows), [&](const tbb::blocked_range<int>& rows) {
        CellRecorder& recorder = learner.recorder();
        for (int by = rows.begin(); by != rows.end(); ++by) {
            if (context.cancelled() || out_of_time()) return;
            for (int bx = 0; bx < blocks.columns; ++bx) {
                const uint64_t block = uint64_t(by) * uint64_t(blocks.columns) + uint64_t(bx);
                // The block's pixel (the pixel itself when b = 1), from the block's own stream.
                Sampler pick(context.seed, block, 0, kLearningPassStream + 1);
                const Vec2f u = pick.next_2d();
                const int x = std::min(W - 1, bx * blocks.b + std::min(blocks.b - 1, int(u.x * float(blocks.b))));
                const int y = std::min(H - 1, by * blocks.b + std::min(blocks.b - 1, int(u.y * float(blocks.b))));
                for (int k = budget.first_sample; k < budget.first_sample + budget.spp; ++k) {
                    Sampler sampler(context.seed, uint64_t(y) * uint64_t(W) + uint64_t(x), uint64_t(k),
                                    kLearningPassStream);
                    const Point2f pos = film_position(x, y, sampler.next_2d());
                    const Point2f film_uv(pos.x / float(W), pos.y / float(H));
                    recorder.begin(learner.pixel(film_uv), pixel(film_uv));
                    camera_sample_value(sensor, film_uv,
                                        [&](const CameraRay& camera) { return walk(sampler, camera, recorder); });
                    recorder.end();
                }
            }
            paths += uint64_t(blocks.columns) * uint64_t(std::max(0, budget.spp));
        }
    });
    learner.end_pass();
    return paths.load();
}

}  // namespace volguide
