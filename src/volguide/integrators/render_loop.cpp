#include "volguide/integrators/render_loop.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "volguide/core/cpu_time.h"
#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/light_tracing.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensors/film_buffer.h"
#include "volguide/render/sensors/rfilters.h"

namespace volguide {

int pass_size(int index) {
    return index <= 1 ? 1 : std::min(1 << std::min(index - 1, 3), 8);
}

std::vector<int> pass_schedule(int spp) {
    std::vector<int> passes;
    for (int done = 0, k = 0; done < spp; ++k) {
        int n = std::min(pass_size(k), spp - done);
        passes.push_back(n);
        done += n;
    }
    return passes;
}

std::vector<PixelRect> make_tiles(int W, int H, int border, int T) {
    std::vector<PixelRect> tiles;
    for (int y = -border; y < H + border; y += T)
        for (int x = -border; x < W + border; x += T)
            tiles.push_back({x, y, std::min(x + T, W + border), std::min(y + T, H + border)});
    return tiles;
}

bool stopped_before_pass(const RenderOptions& options, std::chrono::steady_clock::time_point deadline, bool first,
                         RenderStats& stats) {
    if (options.cancel && options.cancel->load()) return stats.cancelled = true;
    if (!first && std::chrono::steady_clock::now() >= deadline) return stats.time_limited = true;
    return false;
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// Throttled, serialised progress reporting (called from worker threads).
class ProgressReporter {
  public:
    ProgressReporter(const ProgressCallback& cb, Clock::time_point job_start, double budget, int target)
        : cb_(cb), job_start_(job_start), budget_(budget), target_(target) {}
    void set_render_start(Clock::time_point t) { render_start_ = t; }
    // `spp_progress` = completed spp plus the completed share of the current pass.
    void report(int spp_done, double spp_progress, bool force) {
        if (!cb_) return;
        std::unique_lock lock(mutex_, std::defer_lock);
        if (force)
            lock.lock();
        else if (!lock.try_lock())
            return;
        auto now = Clock::now();
        if (!force && now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        Progress p;
        p.phase = "rendering";
        p.spp_done = spp_done;
        p.spp_target = target_;
        p.elapsed = std::chrono::duration<double>(now - job_start_).count();
        double f_spp = target_ > 0 ? spp_progress / target_ : 0.0;
        double f_time = budget_ > 0 ? p.elapsed / budget_ : 0.0;
        p.fraction = std::clamp(std::max(f_spp, f_time), 0.0, 1.0);
        double eta = -1;  // unknown
        const double render_elapsed = std::chrono::duration<double>(now - render_start_).count();
        // Extrapolate only once the rate means something.
        if (target_ > 0 && f_spp > 0 && (render_elapsed > 1.0 || f_spp > 0.05))
            eta = render_elapsed * (1.0 - f_spp) / f_spp;
        if (budget_ > 0) {
            double left = std::max(0.0, budget_ - p.elapsed);
            eta = eta < 0 ? left : std::min(eta, left);
        }
        p.eta = eta;
        cb_(p);
    }

  private:
    const ProgressCallback& cb_;
    Clock::time_point job_start_, render_start_, last_{};
    double budget_;
    int target_;
    std::mutex mutex_;
};

int arena_threads(int requested) {
    if (requested < 0) throw std::invalid_argument("render: thread count must be >= 0");
    return requested > 0 ? requested : tbb::task_arena::automatic;
}

// An explicit thread count may exceed the hardware's: lift TBB's worker limit for the render.
std::unique_ptr<tbb::global_control> thread_limit(int requested) {
    if (requested <= 0) return nullptr;
    return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                 size_t(requested));
}

// What the tiles of one pass leave: their buffers and non-finite samples (merged in tile order),
// and whether the pass was stopped.
// One pixel's samples of a pass (their luminance): count, sum and sum of squares.
struct PixelSamples {
    int n = 0;
    double sum = 0, sum_sq = 0;
    void add(double v) {
        ++n;
        sum += v;
        sum_sq += v * v;
    }
};

// PassReport::relative_variance summed over pixels (a tile's, then the pass's in tile order).
struct PixelNoise {
    double relative_variance = 0, relative_variance_sq = 0;
    uint64_t pixels = 0;
    // The benchmark's relMSE epsilon (bench/run_bench.py): dark pixels do not dominate.
    static constexpr double kEpsilon = 0.01;
    // `scale`: the pixel's 1 / (mean^2 + epsilon), fixed for the render (NoiseScale).
    void add(const PixelSamples& p, float scale) {
        if (p.n < 2) return;
        const double mean = p.sum / p.n;
        const double variance = std::max(0.0, (p.sum_sq - p.sum * mean) / (p.n - 1));
        const double v = variance * double(scale);
        relative_variance += v;
        relative_variance_sq += v * v;
        ++pixels;
    }
    PixelNoise& operator+=(const PixelNoise& o) {
        relative_variance += o.relative_variance;
        relative_variance_sq += o.relative_variance_sq;
        pixels += o.pixels;
        return *this;
    }
    double mean() const {
        return pixels > 0 ? relative_variance / double(pixels) : std::numeric_limits<double>::quiet_NaN();
    }
    // The standard error of mean() over the pixels (independent samples per pixel).
    double error() const {
        if (pixels < 2) return std::numeric_limits<double>::quiet_NaN();
        const double m = mean();
        return std::sqrt(std::max(0.0, relative_variance_sq / double(pixels) - m * m) / double(pixels - 1));
    }
};

struct PassOutput {
    explicit PassOutput(size_t tiles) : buffers(tiles), nonfinite(tiles, 0), first_bad(tiles), noise(tiles) {}
    std::vector<std::unique_ptr<TileBuffer>> buffers;
    std::vector<uint64_t> nonfinite;
    std::vector<SampleLocation> first_bad;
    std::vector<PixelNoise> noise;
    std::atomic<bool> stop_cancel{false}, stop_time{false};
    std::atomic<uint64_t> samples_done{0};
};

// One render_frame call: the frame's fixed setup and its passes.
class FrameRenderer {
  public:
    FrameRenderer(const FrameSetup& setup, const RadianceFn& radiance, const RenderOptions& options,
                  tbb::task_arena& arena, Clock::time_point job_start)
        : setup_(setup),
          radiance_(radiance),
          options_(options),
          arena_(arena),
          job_start_(job_start),
          seed_(options.seed.value_or(setup.seed)),
          budget_(options.time_budget > 0 ? options.time_budget : 0.0),
          // 0 = unbounded: only the time budget (or a cancel) ends the render.
          target_(options.spp > 0 ? options.spp : (budget_ > 0 ? 0 : std::max(setup.default_spp, 1))),
          deadline_(budget_ > 0 ? job_start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(budget_))
                                : Clock::time_point::max()),
          // Samples are taken over the film, plus the filter's border when sample_border is set.
          grid_{setup.width, setup.height, setup.sample_border ? filter_border_size(*setup.filter) : 0},
          tiles_(make_tiles(setup.width, setup.height, grid_.border, options.tile_size)),
          splatter_(*setup.filter, setup.width, setup.height),
          film_(setup.width, setup.height, setup.variance),
          reporter_(options.progress, job_start, budget_, target_) {}

    RenderResult run() {
        RenderResult result;
        RenderStats& stats = result.stats;
        stats.seed = seed_;
        stats.threads = arena_.max_concurrency();
        reporter_.set_render_start(Clock::now());
        const auto render_start = Clock::now();
        const double cpu_start = process_cpu_seconds();
        int spp_done = options_.resume ? restore(*options_.resume, stats) : 0;
        bool resumable = true;  // whether the state after the last merged pass may be checkpointed
        for (int pass = stats.passes; target_ == 0 || spp_done < target_; ++pass) {
            if (stopped_before_pass(options_, deadline_, spp_done == 0, stats)) break;
            const int n = target_ > 0 ? std::min(pass_size(pass), target_ - spp_done) : pass_size(pass);
            const auto pass_start = Clock::now();
            PassReport report;
            if (!run_pass(spp_done, n, stats, report)) break;
            spp_done += n;
            reporter_.report(spp_done, spp_done, true);
            report.spp_done = spp_done;
            report.spp = n;
            report.pass_seconds = seconds_since(pass_start);
            report.seconds = seconds_since(job_start_);
            if (options_.end_pass) options_.end_pass(report);
            // A stop asked for before the integrator's learning from the pass ended may have cut it short
            // (guided_volpath's full stage stops its photons at a cancel): that state is not the
            // uninterrupted render's, so it is never checkpointed; the last checkpoint stays.
            resumable = !(options_.cancel && options_.cancel->load());
            if (options_.on_pass) options_.on_pass(spp_done, seconds_since(job_start_), film_.mean());
            if (resumable) checkpoint(spp_done, stats, false);
        }
        if (spp_done > 0 && resumable) checkpoint(spp_done, stats, true);
        result.spp = spp_done;
        result.first_sample = options_.first_sample;
        result.mean = film_.mean();
        result.weight = film_.weights();
        if (setup_.variance) result.variance = film_.variance();
        stats.render_seconds = seconds_since(render_start);
        stats.render_cpu_seconds = process_cpu_seconds() - cpu_start;
        stats.total_seconds = seconds_since(job_start_);
        return result;
    }

  private:
    // The film, passes and counters of a checkpoint; returns its samples per pixel.
    int restore(const RenderState& state, RenderStats& stats) {
        if (state.first_sample != options_.first_sample)
            throw std::invalid_argument("render: the checkpoint's first sample differs from the render's");
        if (target_ > 0 && state.spp_done > target_)
            throw std::invalid_argument("render: the checkpoint has more samples per pixel than the render's target");
        if (!state.noise_scale.empty() && state.noise_scale.size() != size_t(setup_.width) * size_t(setup_.height))
            throw std::invalid_argument("render: the checkpoint's noise normaliser is of another film size");
        film_.restore(state.film);
        noise_scale_ = state.noise_scale;
        stats.passes = state.passes;
        stats.samples = state.samples;
        stats.nonfinite_samples = state.nonfinite_samples;
        stats.discarded_samples = state.discarded_samples;
        return state.spp_done;
    }

    void checkpoint(int spp_done, const RenderStats& stats, bool final) {
        if (!options_.checkpoint) return;
        options_.checkpoint(
            [&] {
                RenderState state;
                state.passes = stats.passes;
                state.spp_done = spp_done;
                state.first_sample = options_.first_sample;
                state.film = film_.sums();
                state.noise_scale = noise_scale_;
                state.samples = stats.samples;
                state.nonfinite_samples = stats.nonfinite_samples;
                state.discarded_samples = stats.discarded_samples;
                return state;
            },
            final);
    }

    uint64_t grid_samples(int n) const {
        return uint64_t(grid_.width + 2 * grid_.border) * uint64_t(grid_.height + 2 * grid_.border) * uint64_t(n);
    }

    // Samples [spp_done, spp_done + n) of every pixel, merged into the film when the pass completes;
    // false (nothing merged) when it was stopped.
    bool run_pass(int spp_done, int n, RenderStats& stats, PassReport& report) {
        PassOutput out(tiles_.size());
        arena_execute(arena_, [&] {
            parallel_for(tbb::blocked_range<size_t>(0, tiles_.size(), 1),
                         [&](const tbb::blocked_range<size_t>& r) {
                             for (size_t t = r.begin(); t != r.end(); ++t) render_tile(t, spp_done, n, out);
                         });
        });
        if (out.stop_cancel || out.stop_time) {
            stats.discarded_samples += out.samples_done.load();
            stats.cancelled = out.stop_cancel.load();
            stats.time_limited = !stats.cancelled;
            return false;
        }
        // Merge in tile order: the same floating-point sums whatever thread rendered which tile.
        PixelNoise noise;
        for (size_t t = 0; t < tiles_.size(); ++t) {
            noise += out.noise[t];
            film_.add(*out.buffers[t]);
            out.buffers[t].reset();
            stats.nonfinite_samples += out.nonfinite[t];
            if (out.nonfinite[t] > 0 && !stats.first_nonfinite) stats.first_nonfinite = out.first_bad[t];
        }
        stats.passes += 1;
        stats.samples += grid_samples(n);
        report.relative_variance = noise.mean();
        report.relative_variance_error = noise.error();
        if (noise_scale_.empty() && n >= 2) set_noise_scale();
        return true;
    }

    void render_tile(size_t t, int spp_done, int n, PassOutput& out) {
        if (out.stop_cancel.load(std::memory_order_relaxed) || out.stop_time.load(std::memory_order_relaxed)) return;
        const bool first = spp_done == 0;
        const PixelRect& rect = tiles_[t];
        auto buf = std::make_unique<TileBuffer>(splatter_, splatter_.footprint(rect), setup_.variance);
        uint64_t bad = 0;
        PixelNoise noise;
        for (int y = rect.y0; y < rect.y1; ++y) {
            // Stop checks once per row: a cancelled or late pass is dropped as a whole.
            if (options_.cancel && options_.cancel->load(std::memory_order_relaxed)) {
                out.stop_cancel = true;
                return;
            }
            if (!first && Clock::now() >= deadline_) {
                out.stop_time = true;
                return;
            }
            for (int x = rect.x0; x < rect.x1; ++x) {
                PixelSamples pixel;
                for (int k = spp_done; k < spp_done + n; ++k) {
                    const uint64_t s = options_.first_sample + uint64_t(k);
                    FilmSample fs = film_sample(grid_, seed_, x, y, s);
                    const Color3 L = radiance_(fs.film_uv, fs.sampler);
                    if (!L.is_finite()) {
                        if (bad++ == 0) out.first_bad[t] = SampleLocation{x, y, s};
                        continue;
                    }
                    buf->splat(fs.pos, L);
                    pixel.add(L.luminance());
                }
                if (!noise_scale_.empty() && x >= 0 && x < setup_.width && y >= 0 && y < setup_.height)
                    noise.add(pixel, noise_scale_[size_t(y) * size_t(setup_.width) + size_t(x)]);
            }
        }
        out.noise[t] = noise;
        out.nonfinite[t] = bad;
        out.buffers[t] = std::move(buf);
        const uint64_t tile_samples = uint64_t(rect.width()) * rect.height() * n;
        const uint64_t done = out.samples_done.fetch_add(tile_samples) + tile_samples;
        reporter_.report(spp_done, spp_done + double(n) * double(done) / double(grid_samples(n)), false);
    }

    // The per-sample noise's normaliser, fixed for the whole render so that passes of any size compare
    // alike (PassReport::relative_variance): per pixel 1 / (m^2 + epsilon), m the luminance of the
    // image once a pass has two or more samples per pixel. A pass's own mean would sit in the
    // denominator of its own variance, a bias that depends on the pass's sample count; this pass
    // therefore reports no noise, the later ones do.
    void set_noise_scale() {
        const Image mean = film_.mean();
        noise_scale_.resize(size_t(setup_.width) * size_t(setup_.height));
        for (int y = 0; y < setup_.height; ++y)
            for (int x = 0; x < setup_.width; ++x) {
                const double m = mean.at(x, y).luminance();
                noise_scale_[size_t(y) * size_t(setup_.width) + size_t(x)] = float(1.0 / (m * m + PixelNoise::kEpsilon));
            }
    }

    std::vector<float> noise_scale_;
    const FrameSetup& setup_;
    const RadianceFn& radiance_;
    const RenderOptions& options_;
    tbb::task_arena& arena_;
    const Clock::time_point job_start_;
    const uint64_t seed_;
    const double budget_;
    const int target_;
    const Clock::time_point deadline_;
    const FilmGrid grid_;
    const std::vector<PixelRect> tiles_;
    Splatter splatter_;
    FilmBuffer film_;
    ProgressReporter reporter_;
};

RenderResult render_frame_impl(const FrameSetup& setup, const RadianceFn& radiance,
                               const RenderOptions& options, tbb::task_arena& arena,
                               Clock::time_point job_start) {
    if (setup.width <= 0 || setup.height <= 0) throw std::invalid_argument("render: empty film");
    if (!setup.filter) throw std::invalid_argument("render: no reconstruction filter");
    if (options.spp < 0) throw std::invalid_argument("render: spp must be >= 0");
    if (options.tile_size <= 0) throw std::invalid_argument("render: tile size must be positive");
    return FrameRenderer(setup, radiance, options, arena, job_start).run();
}

}  // namespace

RenderResult render_frame(const FrameSetup& setup, const RadianceFn& radiance, const RenderOptions& options) {
    auto limit = thread_limit(options.threads);
    tbb::task_arena arena(arena_threads(options.threads));
    return render_frame_impl(setup, radiance, options, arena, Clock::now());
}

RenderResult render(Scene& scene, const RenderOptions& options) {
    // The scene owns its integrator; preprocessing (training) mutates it before rendering.
    return render(scene, const_cast<Integrator&>(scene.integrator()), options);
}

namespace {

void preprocess_in(tbb::task_arena& arena, const Scene& scene, Integrator& integrator, const RenderOptions& options,
                   bool saved) {
    if (options.progress) {
        Progress p;
        p.phase = "preprocess";
        p.spp_target = options.spp;
        options.progress(p);
    }
    PreprocessContext context;
    context.seed = options.seed.value_or(scene.sensor().seed());
    context.time_budget = options.time_budget;
    context.spp = options.spp > 0 ? options.spp : (options.time_budget > 0 ? 0 : scene.sensor().sample_count());
    context.progress = options.progress;
    context.cancel = options.cancel;
    context.learn_in_prepass = saved;
    arena_execute(arena, [&] { integrator.preprocess(scene, context); });
}

// A resumed render's integrator: what it had learned by the checkpoint, after its preprocess().
void resume_integrator(tbb::task_arena& arena, Integrator& integrator, const RenderOptions& options) {
    if (integrator.traces_from_emitters() && (options.resume || options.checkpoint))
        throw std::invalid_argument("render: light tracers (" + integrator.configuration() +
                                    ") have no checkpoints");
    if (options.resume) arena_execute(arena, [&] { integrator.restore_render_state(options.resume->integrator); });
}

}  // namespace

double run_preprocess(const Scene& scene, Integrator& integrator, const RenderOptions& options) {
    const auto start = Clock::now();
    auto limit = thread_limit(options.threads);
    tbb::task_arena arena(arena_threads(options.threads));
    preprocess_in(arena, scene, integrator, options, true);
    return seconds_since(start);
}

RenderResult render(const Scene& scene, Integrator& integrator, const RenderOptions& options) {
    const auto job_start = Clock::now();
    auto limit = thread_limit(options.threads);
    tbb::task_arena arena(arena_threads(options.threads));
    preprocess_in(arena, scene, integrator, options, false);
    const double preprocess_seconds = seconds_since(job_start);

    const Sensor& sensor = scene.sensor();
    const Film& film = sensor.film();
    FrameSetup setup;
    setup.width = film.width();
    setup.height = film.height();
    setup.filter = &film.filter();
    setup.sample_border = film.sample_border();
    setup.default_spp = sensor.sample_count();
    setup.seed = sensor.seed();
    setup.variance = integrator.writes_variance() || options.variance;
    RadianceFn radiance = [&](Point2f uv, Sampler& sampler) {
        return camera_sample_value(scene, integrator, uv, sampler);
    };
    // The integrator may learn from each pass (Integrator::end_pass), within the render's arena.
    RenderOptions pass_options = options;
    pass_options.end_pass = [&](const PassReport& pass) {
        arena_execute(arena, [&] { integrator.end_pass(pass); });
        if (options.end_pass) options.end_pass(pass);
    };
    resume_integrator(arena, integrator, options);
    if (options.checkpoint)
        pass_options.checkpoint = [&](const std::function<RenderState()>& state, bool final) {
            options.checkpoint(
                [&] {
                    RenderState s = state();
                    s.integrator = integrator.render_state();
                    return s;
                },
                final);
        };
    RenderResult result = integrator.traces_from_emitters()
                              ? render_light_tracing(scene, integrator, pass_options, arena, job_start)
                              : render_frame_impl(setup, radiance, pass_options, arena, job_start);
    result.stats.preprocess_seconds = preprocess_seconds;
    return result;
}

}  // namespace volguide
