#include "volguide/integrators/guided_volpath.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "volguide/core/log.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided_walk_policy.h"
#include "volguide/integrators/medium_occupancy.h"
#include "volguide/integrators/photon_pass.h"
#include "volguide/integrators/progressive_training.h"
#include "volguide/render/image_io.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {

// Iteration k traces 2^k spp: 20 iterations are already ~10^6 spp.
constexpr int64_t kMaxTrainingIterations = 20;

// Points per leaf measuring its medium fraction: ~4 % standard error for a half-filled leaf.
constexpr int kOccupancyPoints = 128;

// A choice among `allowed`; `implemented` lists those that exist today. The default (parameter
// absent) falls back to `fallback` with a warning when it is not implemented; an explicit request
// for an unimplemented value is an error (interface.md).
std::string read_choice(const Properties& props, const std::string& name, const std::string& def,
                        std::initializer_list<const char*> allowed,
                        std::initializer_list<const char*> implemented, const std::string& fallback) {
    const bool given = props.has(name);
    const std::string value = props.get_string(name, def);
    auto in = [&](std::initializer_list<const char*> list) {
        for (const char* v : list)
            if (value == v) return true;
        return false;
    };
    if (!in(allowed)) {
        std::string options;
        for (const char* v : allowed) options += (options.empty() ? "" : ", ") + std::string(v);
        props.fail_at(name, "guided_volpath: invalid {} '{}' (one of: {})", name, value, options);
    }
    if (in(implemented)) return value;
    if (given) props.fail_at(name, "guided_volpath: {}={} is not implemented yet", name, value);
    warn(props.location(), "guided_volpath: {}={} (the default) is not implemented yet; using {}={}", name,
         value, name, fallback);
    return fallback;
}

}  // namespace

GuidedVolPathSettings GuidedVolPathSettings::from(const Properties& props) {
    GuidedVolPathSettings s;
    s.location = props.location();
    s.walk = VolPathSettings::from(props);
    s.training = read_choice(props, "training", "photons", {"photons", "progressive"},
                             {"photons", "progressive"}, "photons");
    s.photons = props.get_int("photons", s.photons);
    if (s.photons < 1) props.fail_at("photons", "guided_volpath: photons must be >= 1, got {}", s.photons);
    s.max_deposits = props.get_int("max_deposits", s.max_deposits);
    if (s.max_deposits < 0)
        props.fail_at("max_deposits", "guided_volpath: max_deposits must be >= 0 (0: no cap), got {}",
                      s.max_deposits);
    s.photon_focus = props.get_bool("photon_focus", s.photon_focus);
    const int64_t iterations = props.get_int("training_iterations", s.training_iterations);
    if (iterations < 1 || iterations > kMaxTrainingIterations)
        props.fail_at("training_iterations", "guided_volpath: training_iterations must be in [1, {}], got {}",
                      kMaxTrainingIterations, iterations);
    s.training_iterations = int(iterations);
    s.training_fraction = props.get_float("training_fraction", s.training_fraction);
    if (!(s.training_fraction > 0.f && s.training_fraction < 1.f))
        props.fail_at("training_fraction", "guided_volpath: training_fraction must be in (0, 1), got {}",
                      s.training_fraction);
    const int64_t leaf_samples = props.get_int("leaf_samples", 2000);
    if (leaf_samples < 1)
        props.fail_at("leaf_samples", "guided_volpath: leaf_samples must be >= 1, got {}", leaf_samples);
    s.field.tree.max_samples = int(std::min<int64_t>(leaf_samples, 1 << 30));
    const int64_t lobes = props.get_int("lobes", s.field.lobes);
    if (lobes < 1 || lobes > kVmmMaxLobes)
        props.fail_at("lobes", "guided_volpath: lobes must be in [1, {}], got {}", kVmmMaxLobes, lobes);
    s.field.lobes = int(lobes);
    // The guided decisions: distance, direction, RR and splitting (the paper's full system by default).
    s.distance = read_choice(props, "distance", "incremental", {"standard", "incremental", "tabulated"},
                             {"standard", "incremental", "tabulated"}, "standard");
    auto unit_interval = [&](const char* name, float def, bool open_top) {
        const float v = props.get_float(name, def);
        if (!(v >= 0.f && (open_top ? v < 1.f : v <= 1.f)))
            props.fail_at(name, "guided_volpath: {} must be in [0, 1{}, got {}", name, open_top ? ")" : "]",
                          v);
        return v;
    };
    s.guide.distance_settings.c_T = unit_interval("c_T", s.guide.distance_settings.c_T, false);
    s.guide.distance_settings.p_max = props.get_float("p_max", s.guide.distance_settings.p_max);
    if (!(s.guide.distance_settings.p_max > 0.f && s.guide.distance_settings.p_max <= 1.f))
        props.fail_at("p_max", "guided_volpath: p_max must be in (0, 1], got {}",
                      s.guide.distance_settings.p_max);
    s.guide.distance_settings.filter_A = unit_interval("filter_A", s.guide.distance_settings.filter_A, false);
    s.guide.distance_settings.denominator =
        read_choice(props, "distance_denominator", "vre", {"vre", "incident"}, {"vre", "incident"}, "vre") ==
                "vre"
            ? DistanceDenominator::Vre
            : DistanceDenominator::Incident;
    s.guide.phase_prob = unit_interval("phase_prob", s.guide.phase_prob, false);
    s.guide.direction_indirect = read_choice(props, "direction_radiance", "indirect", {"indirect", "all"},
                                             {"indirect", "all"}, "indirect") == "indirect";
    s.guide.surface = props.get_bool("surface_guiding", s.guide.surface);
    s.guide.bsdf_prob = unit_interval("bsdf_prob", s.guide.bsdf_prob, false);
    s.guide.leaf_tau_max = props.get_float("leaf_tau_max", s.guide.leaf_tau_max);
    if (!(s.guide.leaf_tau_max >= 0.f) || std::isinf(s.guide.leaf_tau_max))
        props.fail_at("leaf_tau_max",
                      "guided_volpath: leaf_tau_max must be a finite value >= 0 (0: off), got {}",
                      s.guide.leaf_tau_max);
    const int64_t table = props.get_int("estimate_table", s.guide.estimate_table);
    if (table < 0 || table > 256)
        props.fail_at("estimate_table",
                      "guided_volpath: estimate_table must be in [0, 256] (0: exact), got {}", table);
    s.guide.estimate_table = int(table);
    if (s.distance != "standard" && s.walk.equiangular)
        props.fail_at("equiangular",
                      "guided_volpath: equiangular sampling cannot be combined with distance={}", s.distance);
    s.guide.distance = s.distance == "incremental" ? DistanceGuiding::Incremental
                       : s.distance == "tabulated" ? DistanceGuiding::Tabulated
                                                   : DistanceGuiding::Standard;
    // Heterogeneous media under distance=incremental: guided null-collision tracking (H2) or the bins (H1).
    s.guide.guided_tracking = read_choice(props, "hetero_distance", "tracking", {"tracking", "bins"},
                                          {"tracking", "bins"}, "tracking") == "tracking";
    s.direction = read_choice(props, "direction", "product", {"phase", "incident", "product"},
                              {"phase", "incident", "product"}, "phase");
    s.guide.direction = s.direction == "product"    ? DirectionGuiding::Product
                        : s.direction == "incident" ? DirectionGuiding::Incident
                                                    : DirectionGuiding::Phase;
    s.rrs = read_choice(props, "rrs", "grrs", {"standard", "grr", "grrs"}, {"standard", "grr", "grrs"}, "standard");
    s.roulette.mode = s.rrs == "grrs"  ? RouletteMode::GuidedSplitting
                      : s.rrs == "grr" ? RouletteMode::Guided
                                       : RouletteMode::Standard;
    s.roulette.window = props.get_float("rrs_window", s.roulette.window);
    if (!(s.roulette.window >= 1.f) || std::isinf(s.roulette.window))
        props.fail_at("rrs_window", "guided_volpath: rrs_window must be a finite value >= 1, got {}",
                      s.roulette.window);
    s.roulette.q_min = props.get_float("rrs_q_min", s.roulette.q_min);
    if (!(s.roulette.q_min > 0.f && s.roulette.q_min <= 1.f))
        props.fail_at("rrs_q_min", "guided_volpath: rrs_q_min must be in (0, 1], got {}", s.roulette.q_min);
    s.roulette.q_max = props.get_float("rrs_q_max", s.roulette.q_max);
    if (!(s.roulette.q_max >= 1.f) || std::isinf(s.roulette.q_max))
        props.fail_at("rrs_q_max", "guided_volpath: rrs_q_max must be a finite value >= 1, got {}", s.roulette.q_max);
    const int64_t branches = props.get_int("rrs_max_branches", s.roulette.max_branches);
    if (branches < 1 || branches > 4096)
        props.fail_at("rrs_max_branches", "guided_volpath: rrs_max_branches must be in [1, 4096], got {}", branches);
    s.roulette.max_branches = int(branches);
    s.pixel_estimate = read_choice(props, "pixel_estimate", "raymarch", {"raymarch", "render"},
                                   {"raymarch", "render"}, "raymarch");
    const int64_t rays = props.get_int("pixel_estimate_rays", s.pixel.rays_per_pixel);
    if (rays < 1 || rays > 1024)
        props.fail_at("pixel_estimate_rays", "guided_volpath: pixel_estimate_rays must be in [1, 1024], got {}", rays);
    s.pixel.rays_per_pixel = int(rays);
    const int64_t spp = props.get_int("pixel_estimate_spp", s.pixel_estimate_spp);
    if (spp < 1 || spp > 4096)
        props.fail_at("pixel_estimate_spp", "guided_volpath: pixel_estimate_spp must be in [1, 4096], got {}", spp);
    s.pixel_estimate_spp = int(spp);
    s.pixel.floor_fraction = props.get_float("pixel_estimate_floor", s.pixel.floor_fraction);
    if (!(s.pixel.floor_fraction > 0.f) || std::isinf(s.pixel.floor_fraction))
        props.fail_at("pixel_estimate_floor", "guided_volpath: pixel_estimate_floor must be a finite value > 0, got {}",
                      s.pixel.floor_fraction);
    if (props.has("save_pixel_estimate")) s.save_pixel_estimate = props.get_string("save_pixel_estimate");
    s.pixel.volume_only = s.walk.volume_only;
    s.pixel.hide_emitters = s.walk.hide_emitters;
    if (s.rrs == "standard")
        for (const char* name : {"rrs_window", "rrs_q_min", "rrs_q_max", "rrs_max_branches", "pixel_estimate",
                                 "pixel_estimate_rays", "pixel_estimate_spp", "pixel_estimate_floor",
                                 "save_pixel_estimate"})
            if (props.has(name))
                props.fail_at(name, "guided_volpath: {} only applies to rrs=grr or rrs=grrs (rrs=standard)", name);
    s.estimate = read_choice(props, "estimate", "none", {"none", "inscattered", "incident"},
                             {"none", "inscattered", "incident"}, "none");
    if (props.has("save_field")) s.save_field = props.get_string("save_field");
    if (props.has("load_field")) {
        std::filesystem::path p(props.get_string("load_field"));
        // Like Mitsuba's file resolver: a relative path that does not exist here is looked up
        // beside the scene file.
        if (p.is_relative() && !std::filesystem::exists(p)) {
            const auto beside = std::filesystem::path(props.location_of("load_field").file).parent_path() / p;
            if (std::filesystem::exists(beside)) p = beside;
        }
        s.load_field = p.string();
        if (!std::filesystem::exists(p))
            props.fail_at("load_field", "guided_volpath: the guiding field \"{}\" does not exist",
                          s.load_field);
    }
    return s;
}

GuidedVolPathIntegrator::GuidedVolPathIntegrator(const Properties& props)
    : settings_(GuidedVolPathSettings::from(props)), walk_(settings_.walk) {}

BBox3f guiding_bounds(const Scene& scene) {
    BBox3f b = scene.bbox();
    if (!b.valid()) return BBox3f(Point3f(-1.f), Point3f(1.f));
    // A little margin so that collisions on the bounding surfaces fall inside.
    const Vec3f margin = b.extents() * 1e-3f + Vec3f(1e-4f);
    return BBox3f(b.lo - margin, b.hi + margin);
}

void GuidedVolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext& context) {
    training_stats_.clear();
    walk_.preprocess(scene, context);
    if (!settings_.load_field.empty()) {
        try {
            field_ = load_field(settings_.load_field);
        } catch (const FieldFormatError& e) {
            throw InputError(settings_.location, e.what());
        }
    } else if (settings_.training == "progressive") {
        ProgressiveTrainingSettings ts;
        ts.walk = settings_.walk;
        ts.iterations = settings_.training_iterations;
        if (context.time_budget > 0) ts.time_limit = settings_.training_fraction * context.time_budget;
        ts.field = settings_.field;
        field_ = train_progressive(scene, guiding_bounds(scene), ts, context).field;
    } else {
        PhotonPassSettings ps;
        ps.photons = settings_.photons;
        ps.max_deposits = settings_.max_deposits;
        ps.focus = settings_.photon_focus;
        ps.max_depth = settings_.walk.max_depth;
        ps.rr_depth = settings_.walk.rr_depth;
        // Under a --time budget, training gets training_fraction of it (interface.md).
        if (context.time_budget > 0) ps.time_limit = settings_.training_fraction * context.time_budget;
        const PhotonPassResult photons = trace_photons(scene, ps, context);
        training_stats_ = {
            {"photons_traced", double(photons.photons_traced)},
            {"photons_pilot", double(photons.pilot_photons)},
            {"photons_depositing_fraction",
             photons.photons_traced > 0 ? double(photons.photons_depositing) / double(photons.photons_traced)
                                        : 0.0},
            {"photon_deposits", double(photons.samples.size())},
            {"photon_deposit_limited", photons.deposit_limited ? 1.0 : 0.0}};
        field_ = GuidingField::build(guiding_bounds(scene), photons.samples, settings_.field);
        // Per-volume fluence counts collisions, which only happen inside media.
        field_.apply_medium_fractions(medium_fractions(scene, field_.tree(), kOccupancyPoints, context.seed));
    }
    estimator_.reset();
    if (settings_.estimate != "none") estimator_ = std::make_unique<CacheEstimator>(scene, field_);
    guide_.reset();
    rrs_.reset();
    pixel_estimate_ = PixelEstimate();
    if (settings_.guide.distance != DistanceGuiding::Standard ||
        settings_.guide.direction != DirectionGuiding::Phase || settings_.roulette.mode != RouletteMode::Standard)
        guide_ = std::make_unique<WalkGuide>(scene, field_, settings_.guide);
    if (settings_.roulette.mode != RouletteMode::Standard && !estimator_) {
        // The pixel estimate I (theory.md §9.5), once, from the finished field.
        const auto start = std::chrono::steady_clock::now();
        if (context.progress) {
            Progress p;
            p.phase = "pixel estimate";
            context.progress(p);
        }
        if (settings_.pixel_estimate == "render") {
            pixel_estimate_ = PixelEstimate::render(
                scene,
                [&](Sampler& sampler, const Ray& ray) { return guided_walk(scene, sampler, ray, 0.f); },
                settings_.pixel_estimate_spp, settings_.pixel, context);
        } else {
            const CacheEstimator marcher(scene, field_);
            pixel_estimate_ = PixelEstimate::raymarch(scene, field_, marcher, settings_.pixel, context);
        }
        if (!settings_.save_pixel_estimate.empty()) {
            try {
                write_exr(settings_.save_pixel_estimate, pixel_estimate_.image());
            } catch (const std::exception& e) {
                throw InputError(settings_.location, fmt::format("guided_volpath: cannot write the pixel estimate: {}",
                                                                 e.what()));
            }
        }
        rrs_ = std::make_unique<RouletteSplitting>(settings_.roulette);
        rrs_->set_pixel_estimate_seconds(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    if (!settings_.save_field.empty()) {
        try {
            save_field(settings_.save_field, field_);
        } catch (const FieldFormatError& e) {
            throw InputError(settings_.location, e.what());
        }
    }
}

Color3 GuidedVolPathIntegrator::guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray, float pixel) const {
    if (!guide_) return walk_.walk(scene, sampler, ray, nullptr);
    GuidedWalkPolicy policy(*guide_, rrs_.get(), pixel);
    return walk_.walk(scene, sampler, ray, &policy);
}

Color3 GuidedVolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    if (estimator_) {
        const CacheQuantity q =
            settings_.estimate == "incident" ? CacheQuantity::Incident : CacheQuantity::Inscattered;
        return estimator_->estimate(camera.ray, scene.sensor().medium(), q, sampler);
    }
    return guided_walk(scene, sampler, camera.ray, rrs_ ? pixel_estimate_.at(camera.film_uv) : 0.f);
}

std::vector<std::pair<std::string, double>> GuidedVolPathIntegrator::statistics() const {
    std::vector<std::pair<std::string, double>> stats = training_stats_;
    if (guide_) {
        const auto walk = guide_->stats().named();
        stats.insert(stats.end(), walk.begin(), walk.end());
    }
    if (rrs_) {
        const auto rr = rrs_->stats().named();
        stats.insert(stats.end(), rr.begin(), rr.end());
    }
    return stats;
}

std::string GuidedVolPathIntegrator::to_string() const {
    const GuidedVolPathSettings& s = settings_;
    return fmt::format(
        "guided_volpath[max_depth={}, rr_depth={}, training={}, photons={}, training_iterations={}, "
        "leaf_samples={}, "
        "lobes={}, distance={}, hetero_distance={}, direction={}, surface_guiding={}, rrs={}, rrs_window={}, "
        "pixel_estimate={}, equiangular={}, estimate={}]",
        s.walk.max_depth, s.walk.rr_depth, s.training, s.photons, s.training_iterations,
        s.field.tree.max_samples, s.field.lobes, s.distance, s.guide.guided_tracking ? "tracking" : "bins",
        s.direction, s.guide.surface, s.rrs, s.roulette.window, s.pixel_estimate, s.walk.equiangular, s.estimate);
}

}  // namespace volguide
