#include "volguide/integrators/light_tracing.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensors/film_buffer.h"
#include "volguide/render/sensors/rfilters.h"

namespace volguide {

namespace {

using Clock = std::chrono::steady_clock;

// Tiles whose splats are held at once before they are added in order (bounds the memory of a pass).
constexpr size_t kTilesPerWave = 64;

struct LightSplat {
    Point2f pos;
    Color3 value;
};

// One tile's light paths: their splats in path order, and the non-finite ones dropped.
struct LightTile : FilmSplats {
    std::vector<LightSplat> splats;
    uint64_t nonfinite = 0;
    void splat(Point2f pos, const Color3& value) override {
        if (!value.is_finite()) {
            ++nonfinite;
            return;
        }
        if (!value.is_black()) splats.push_back({pos, value});
    }
};

// The film's sums: a splat spread over the pixels the filter reaches, its weights normalised to 1.
class SplatFilm {
  public:
    SplatFilm(const ReconstructionFilter& filter, int width, int height)
        : splatter_(filter, width, height), sum_(3 * size_t(width) * size_t(height), 0.0) {}
    void add(const LightSplat& s) {
        const int w = splatter_.film_width(), h = splatter_.film_height();
        if (splatter_.is_box()) {
            const int x = int(std::floor(s.pos.x)), y = int(std::floor(s.pos.y));
            if (x >= 0 && x < w && y >= 0 && y < h) add_pixel(x, y, s.value, 1.0);
            return;
        }
        add_filtered(s);
    }
    Image image(int spp) const {
        const int w = splatter_.film_width(), h = splatter_.film_height();
        Image img(w, h);
        const double inv = spp > 0 ? 1.0 / spp : 0.0;
        for (size_t p = 0; p < size_t(w) * size_t(h); ++p)
            img.pixels[p] =
                Color3(float(sum_[3 * p] * inv), float(sum_[3 * p + 1] * inv), float(sum_[3 * p + 2] * inv));
        return img;
    }

  private:
    void add_pixel(int x, int y, const Color3& v, double w) {
        const size_t p = 3 * (size_t(y) * size_t(splatter_.film_width()) + size_t(x));
        for (int c = 0; c < 3; ++c) sum_[p + c] += double(v[c]) * w;
    }
    void add_filtered(const LightSplat& s) {
        const float r = splatter_.radius();
        const float qx = s.pos.x - 0.5f, qy = s.pos.y - 0.5f;
        const int x0 = std::max(int(std::ceil(qx - r)), 0),
                  x1 = std::min(int(std::floor(qx + r)), splatter_.film_width() - 1);
        const int y0 = std::max(int(std::ceil(qy - r)), 0),
                  y1 = std::min(int(std::floor(qy + r)), splatter_.film_height() - 1);
        double total = 0.0;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) total += weight(x - qx, y - qy);
        if (!(total > 0.0)) return;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x)
                if (const double w = weight(x - qx, y - qy); w != 0.0) add_pixel(x, y, s.value, w / total);
    }
    double weight(float dx, float dy) const {
        return double(splatter_.filter().eval(dx)) * double(splatter_.filter().eval(dy));
    }

    Splatter splatter_;
    std::vector<double> sum_;
};

class LightTracingRenderer {
  public:
    LightTracingRenderer(const Scene& scene, const Integrator& integrator, const RenderOptions& options,
                         tbb::task_arena& arena, Clock::time_point job_start)
        : scene_(scene),
          integrator_(integrator),
          options_(options),
          arena_(arena),
          job_start_(job_start),
          seed_(options.seed.value_or(scene.sensor().seed())),
          width_(scene.sensor().film().width()),
          height_(scene.sensor().film().height()),
          grid_{width_, height_, 0},
          budget_(options.time_budget > 0 ? options.time_budget : 0.0),
          target_(options.spp > 0 ? options.spp
                                  : (budget_ > 0 ? 0 : std::max(scene.sensor().sample_count(), 1))),
          deadline_(budget_ > 0 ? job_start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(budget_))
                                : Clock::time_point::max()),
          tiles_(make_tiles(width_, height_, 0, options.tile_size)),
          film_(scene.sensor().film().filter(), width_, height_) {}

    RenderResult run() {
        RenderResult result;
        result.stats.seed = seed_;
        result.stats.threads = arena_.max_concurrency();
        const auto render_start = Clock::now();
        int spp_done = 0;
        for (int pass = 0; target_ == 0 || spp_done < target_; ++pass) {
            if (stopped_before_pass(options_, deadline_, spp_done == 0, result.stats)) break;
            const int n = target_ > 0 ? std::min(pass_size(pass), target_ - spp_done) : pass_size(pass);
            if (!run_pass(spp_done, n, result.stats)) break;
            spp_done += n;
            report(spp_done);
        }
        result.spp = spp_done;
        result.first_sample = options_.first_sample;
        result.mean = film_.image(spp_done);
        // Every pixel holds spp_done samples' worth: what merging parts weights them by.
        result.weight.assign(size_t(width_) * size_t(height_), double(spp_done));
        result.stats.render_seconds = std::chrono::duration<double>(Clock::now() - render_start).count();
        result.stats.total_seconds = std::chrono::duration<double>(Clock::now() - job_start_).count();
        return result;
    }

  private:
    void report(int spp_done) const {
        const double seconds = std::chrono::duration<double>(Clock::now() - job_start_).count();
        if (options_.progress) {
            Progress p;
            p.phase = "rendering";
            p.spp_done = spp_done;
            p.spp_target = target_;
            p.elapsed = seconds;
            p.fraction = target_ > 0 ? double(spp_done) / target_ : std::min(1.0, seconds / budget_);
            options_.progress(p);
        }
        if (options_.end_pass) {
            PassReport pass;  // no per-pixel noise: a light path lands on many pixels
            pass.spp_done = spp_done;
            pass.seconds = seconds;
            options_.end_pass(pass);
        }
        if (options_.on_pass) options_.on_pass(spp_done, seconds, film_.image(spp_done));
    }

    // Samples [spp_done, spp_done + n) of every pixel's light paths; false (nothing added) when stopped.
    bool run_pass(int spp_done, int n, RenderStats& stats) {
        SplatFilm before = film_;
        uint64_t nonfinite = 0;
        for (size_t begin = 0; begin < tiles_.size(); begin += kTilesPerWave) {
            const size_t end = std::min(begin + kTilesPerWave, tiles_.size());
            std::vector<std::unique_ptr<LightTile>> wave(end - begin);
            std::atomic<bool> stop{false};
            arena_execute(arena_, [&] {
                parallel_for(size_t(0), wave.size(),
                             [&](size_t i) { wave[i] = trace_tile(tiles_[begin + i], spp_done, n, stop); });
            });
            if (stop) {
                film_ = std::move(before);
                stats.discarded_samples += uint64_t(width_) * height_ * n;
                stats.cancelled = options_.cancel && options_.cancel->load();
                stats.time_limited = !stats.cancelled;
                return false;
            }
            for (const auto& tile : wave) {  // in tile order: the same sums for any thread count
                for (const LightSplat& s : tile->splats) film_.add(s);
                nonfinite += tile->nonfinite;
            }
        }
        stats.nonfinite_samples += nonfinite;
        stats.passes += 1;
        stats.samples += uint64_t(width_) * height_ * n;
        return true;
    }

    std::unique_ptr<LightTile> trace_tile(const PixelRect& rect, int spp_done, int n,
                                          std::atomic<bool>& stop) const {
        auto tile = std::make_unique<LightTile>();
        for (int y = rect.y0; y < rect.y1; ++y) {
            // Stop checks once per row: a cancelled or late pass is dropped as a whole.
            if (stop.load(std::memory_order_relaxed) || (options_.cancel && options_.cancel->load()) ||
                (spp_done > 0 && Clock::now() >= deadline_)) {
                stop = true;
                return tile;
            }
            for (int x = rect.x0; x < rect.x1; ++x)
                for (int k = spp_done; k < spp_done + n; ++k) {
                    Sampler sampler(seed_, grid_.pixel_index(x, y), options_.first_sample + uint64_t(k));
                    integrator_.trace_from_emitters(scene_, sampler, *tile);
                }
        }
        return tile;
    }

    const Scene& scene_;
    const Integrator& integrator_;
    const RenderOptions& options_;
    tbb::task_arena& arena_;
    const Clock::time_point job_start_;
    const uint64_t seed_;
    const int width_, height_;
    const FilmGrid grid_;
    const double budget_;
    const int target_;
    const Clock::time_point deadline_;
    const std::vector<PixelRect> tiles_;
    SplatFilm film_;
};

}  // namespace

RenderResult render_light_tracing(const Scene& scene, const Integrator& integrator,
                                  const RenderOptions& options, tbb::task_arena& arena,
                                  Clock::time_point job_start) {
    if (!scene.sensor().supports_connections())
        throw std::invalid_argument(
            "a light tracer (ptracer) needs a pinhole sensor ('perspective' without an aperture)");
    if (options.variance || integrator.writes_variance())
        throw std::invalid_argument("a light tracer (ptracer) has no per-sample variance image");
    if (options.spp < 0) throw std::invalid_argument("render: spp must be >= 0");
    if (options.tile_size <= 0) throw std::invalid_argument("render: tile size must be positive");
    return LightTracingRenderer(scene, integrator, options, arena, job_start).run();
}

}  // namespace volguide
