// guided_volpath's staged pre-pass with the measured per-tile method choice (issue 55; guided_volpath.h).
#include <algorithm>
#include <chrono>
#include <ctime>

#include <fmt/format.h>

#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

constexpr uint64_t kVolpathProbeStream = 0xC401CEull;
constexpr uint64_t kGuidedProbeStream = 0xC401CFull;
// The coarse field's photons: this fraction of `photons`.
constexpr int64_t kCoarsePhotonDivisor = 8;
// Probe rounds (one sample per probe pixel and method each): the render's spp over kProbeSppDivisor, within
// [kMinProbeRounds, kMaxProbeRounds]. Probes cover one pixel in four and run three times (volpath, guided
// on the coarse and on the full field): about 3/64 of the render's samples.
constexpr int kProbeSppDivisor = 16;
constexpr int kMinProbeRounds = 2;
constexpr int kMaxProbeRounds = 16;
// The cheap first stage (volpath probes, coarse field, its guided probes) keeps within this share of the
// pre-pass's time: with training_fraction 0.25, 5 % of the budget on a scene where guiding cannot pay.
constexpr double kFirstStageShare = 0.2;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool GuidedVolPathIntegrator::chooses() const {
    const bool guided = settings_.guide.distance != DistanceGuiding::Standard ||
                        settings_.guide.direction != DirectionGuiding::Phase ||
                        settings_.roulette.mode != RouletteMode::Standard;
    return settings_.method_choice && guided && settings_.estimate == FieldEstimate::None && !given_prepass_ &&
           settings_.load_field.empty();
}

int GuidedVolPathIntegrator::probe_rounds(const PreprocessContext& context) const {
    if (context.spp <= 0) return kMaxProbeRounds;  // a time budget decides
    return std::clamp(context.spp / kProbeSppDivisor, kMinProbeRounds, kMaxProbeRounds);
}

// Probes of bounded volpath; a coarse field and the guided probes on it; when every tile is volpath's,
// training stops (the render is bounded volpath's); else the full field and the guided probes again.
void GuidedVolPathIntegrator::staged_training(const Scene& scene, const PreprocessContext& context,
                                              const PreprocessBudget& budget) {
    const auto start = std::chrono::steady_clock::now();
    const Film& film = scene.sensor().film();
    ChoiceProbes probes(film.width(), film.height());
    const int rounds = probe_rounds(context);
    const int v = run_probes(scene, context, probes, TileMethod::Volpath, rounds,
                             budget.limit_within(0.3, kFirstStageShare * 0.25));
    train_stage(scene, context, std::max<int64_t>(1, settings_.photons / kCoarsePhotonDivisor),
                budget.limit_within(0.4, kFirstStageShare * 0.5));
    build_stage(scene, context, budget.limit_within(0.5, kFirstStageShare * 0.75));
    int g = run_probes(scene, context, probes, TileMethod::Guided, v, budget.limit_within(1.0, kFirstStageShare));
    choice_ = decide_choice(scene, probes);
    if (choice_.volpath_share() >= 1.0) {
        record_choice_stats(1, probes, v, g, seconds_since(start));
        return;
    }
    train_stage(scene, context, settings_.photons, budget.limit(0.5));
    build_stage(scene, context, budget.limit(0.6));
    probes.clear(TileMethod::Guided);
    g = run_probes(scene, context, probes, TileMethod::Guided, v, budget.limit(1.0));
    choice_ = decide_choice(scene, probes);
    record_choice_stats(2, probes, v, g, seconds_since(start));
}

void GuidedVolPathIntegrator::train_stage(const Scene& scene, const PreprocessContext& context, int64_t photons,
                                          double time_limit) {
    PreprocessContext train = context;
    train.time_limit = time_limit;
    field_ = train_by_photons(scene, train, photons, time_limit);
    if (!field_.has_medium_fractions()) measure_medium_fractions(scene, context.seed, true);
}

void GuidedVolPathIntegrator::build_stage(const Scene& scene, const PreprocessContext& context, double time_limit) {
    PreprocessContext build = context;
    build.time_limit = time_limit;
    build_from_field(scene, build, false);
}

int GuidedVolPathIntegrator::run_probes(const Scene& scene, const PreprocessContext& context, ChoiceProbes& probes,
                                        TileMethod method, int rounds, double time_limit) {
    if (context.progress) {
        Progress p;
        p.phase = method == TileMethod::Volpath ? "choice probes (volpath)" : "choice probes (guided)";
        context.progress(p);
    }
    const ChoiceProbes::Walk walk =
        method == TileMethod::Volpath
            ? ChoiceProbes::Walk([&](Sampler& sampler, const CameraRay& camera, WorkCounter& counter) {
                  return bounded_.walk(scene, sampler, camera.ray, nullptr, &counter);
              })
            : ChoiceProbes::Walk([&](Sampler& sampler, const CameraRay& camera, WorkCounter& counter) {
                  const float pixel = rrs_ ? pixel_estimate_.at(camera.film_uv) : 0.f;
                  return guided_walk(scene, sampler, camera.ray, pixel, &counter, camera_guided(camera));
              });
    const uint64_t stream = method == TileMethod::Volpath ? kVolpathProbeStream : kGuidedProbeStream;
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    double last_round = 0;
    int done = 0;
    // At least the rounds the decision needs (ChoiceProbes: 2 samples per pixel for a variance, 4 of volpath's
    // before a tile may go to it), even past the step's limit: without them every tile stays guided.
    const int needed = std::min(rounds, method == TileMethod::Volpath ? 4 : 2);
    for (; done < rounds && !context.cancelled(); ++done) {
        const double t = seconds_since(start);
        if (done >= needed && PreprocessBudget::over(time_limit, t, last_round)) break;
        probes.run_round(scene, method, context.seed, stream, done, walk);
        last_round = seconds_since(start) - t;
    }
    // The last probes' CPU time (all threads; statistics only, the cost model's calibration): less
    // sensitive to a loaded machine than their wall time.
    probe_seconds_[int(method)] = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    return done;
}

ChoiceMap GuidedVolPathIntegrator::decide_choice(const Scene& scene, const ChoiceProbes& probes) const {
    const Film& film = scene.sensor().film();
    return decide_map(film.width(), film.height(), probes.evidence(TileMethod::Guided),
                      probes.evidence(TileMethod::Volpath));
}

// `stage` 1: training stopped after the coarse field (every tile volpath's); 2: the full field.
void GuidedVolPathIntegrator::record_choice_stats(int stage, const ChoiceProbes& probes, int volpath_rounds,
                                                  int guided_rounds, double seconds) {
    const double tiles = double(choice_.tiles.size());
    const double volpath = tiles * choice_.volpath_share();
    training_stats_.insert(training_stats_.end(), {{"choice_stage", double(stage)},
                                                   {"choice_tiles_guided", tiles - volpath},
                                                   {"choice_tiles_volpath", volpath},
                                                   {"choice_volpath_share", choice_.volpath_share()},
                                                   {"choice_probe_rounds_volpath", double(volpath_rounds)},
                                                   {"choice_probe_rounds_guided", double(guided_rounds)},
                                                   {"choice_probe_cpu_seconds_volpath", probe_seconds_[1]},
                                                   {"choice_probe_cpu_seconds_guided", probe_seconds_[0]},
                                                   {"choice_probe_cost_volpath", probes.total_cost(TileMethod::Volpath)},
                                                   {"choice_probe_cost_guided", probes.total_cost(TileMethod::Guided)},
                                                   {"choice_probe_samples_volpath", probes.total_samples(TileMethod::Volpath)},
                                                   {"choice_probe_samples_guided", probes.total_samples(TileMethod::Guided)},
                                                   {"choice_seconds", seconds}});
    static constexpr const char* kCountNames[WorkCounter::kCounts] = {"segments", "medium_vertices", "surface_vertices",
                                                                      "continuations", "branches"};
    for (int k = 0; k < WorkCounter::kCounts; ++k)
        for (TileMethod m : {TileMethod::Volpath, TileMethod::Guided})
            training_stats_.emplace_back(fmt::format("choice_probe_{}_{}", kCountNames[k],
                                                     m == TileMethod::Volpath ? "volpath" : "guided"),
                                         probes.total_count(m, k));
}

}  // namespace volguide
