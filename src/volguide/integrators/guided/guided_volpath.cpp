#include "volguide/integrators/guided/guided_volpath.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "volguide/core/log.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/walk/guided_walk_policy.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/integrators/guided/estimates/selection_pilot.h"
#include "volguide/render/image_io.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

// The pixel estimate's share of the build stage's time limit (the selection pilot gets the rest).
constexpr double kPixelEstimateShare = 0.4;

VolPathSettings bounded_walk(VolPathSettings s) {
    s.rr_rule = RouletteRule::Bounded;
    return s;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

GuidedVolPathIntegrator::GuidedVolPathIntegrator(const Properties& props)
    : settings_(GuidedVolPathSettings::from(props)), walk_(settings_.walk), bounded_(bounded_walk(settings_.walk)) {}

void GuidedVolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext& context) {
    training_stats_.clear();
    work_.clear();
    refining_ = RefinementState{};
    refining_.scene = &scene;
    refining_.seed = context.seed;
    refining_.time_budget = context.time_budget;
    refining_.progress = context.progress;
    refining_.cancel = context.cancel;
    choice_ = ChoiceMap();
    probe_seconds_[0] = probe_seconds_[1] = 0;
    const PreprocessBudget budget(context.time_budget, settings_.training_fraction);
    walk_.preprocess(scene, context);
    bounded_.preprocess(scene, context);
    if (settings_.refine.passes > 0 && given_prepass_)
        throw InputError(settings_.location, "guided_volpath: refine_passes cannot refine a given pre-pass (render "
                                             "--field): it keeps the statistics of the photons it was trained from");
    const auto training_start = std::chrono::steady_clock::now();
    if (chooses()) {
        staged_training(scene, context, budget);
        refining_.training_seconds = seconds_since(training_start);
    } else {
        PreprocessContext train = context;
        train.time_limit = budget.limit(0.6);
        load_or_train_field(scene, train);
        refining_.training_seconds = seconds_since(training_start);
        build_stage(scene, context, budget.limit(1.0));
    }
    if (given_prepass_ && !given_prepass_->choice.empty()) choice_ = ChoiceMap::deserialize(given_prepass_->choice);
    if (budget.limited()) training_stats_.emplace_back("preprocess_limit_seconds", budget.total());
    if (refining_.refinement)
        refining_.schedule = std::make_unique<RefinementSchedule>(settings_.refine, context.time_budget,
                                                                  refining_.training_seconds);
    if (!settings_.save_field.empty()) {
        try {
            save_field(settings_.save_field, field_);
        } catch (const FieldFormatError& e) {
            throw InputError(settings_.location, e.what());
        }
    }
}

// The field's shape in --stats (a refinement replaces the last figures).
void GuidedVolPathIntegrator::record_field_stats() {
    std::erase_if(training_stats_, [](const auto& s) { return s.first.rfind("field_", 0) == 0; });
    int valid = 0;
    for (const GuidingLeaf& leaf : field_.leaves()) valid += leaf.valid;
    training_stats_.insert(training_stats_.end(), {{"field_leaves", double(field_.tree().leaf_count())},
                                                   {"field_valid_leaves", double(valid)},
                                                   {"field_depth", double(field_.tree().depth())}});
}

void GuidedVolPathIntegrator::build_from_field(const Scene& scene, const PreprocessContext& context, bool update) {
    record_field_stats();
    estimator_.reset();
    if (settings_.estimate != FieldEstimate::None) estimator_ = std::make_unique<CacheEstimator>(scene, field_);
    guide_.reset();
    if (!update) rrs_.reset();
    pixel_estimate_ = PixelEstimate();
    pixel_estimate_seconds_ = 0;
    if (settings_.guide.distance != DistanceGuiding::Standard ||
        settings_.guide.direction != DirectionGuiding::Phase || settings_.roulette.mode != RouletteMode::Standard)
        guide_ = std::make_unique<WalkGuide>(scene, field_, settings_.guide);
    // Learned selection's pilot compares with the pixel estimate too.
    const bool learn = guide_ && !estimator_ && settings_.selection.pilot_spp > 0;
    if ((settings_.roulette.mode != RouletteMode::Standard || learn) && !estimator_) {
        if (given_prepass_)
            use_given_pixel_estimate();
        else
            make_pixel_estimate(scene, context);
    } else if (wants_camera_buffer() && !estimator_ && !given_prepass_) {
        make_pixel_estimate(scene, context);  // for distance=vsp's camera-ray buffer only
    }
    if (settings_.roulette.mode != RouletteMode::Standard && !estimator_ && !rrs_) {
        rrs_ = std::make_unique<RouletteSplitting>(settings_.roulette);
        rrs_->set_pixel_estimate_seconds(pixel_estimate_seconds_);
    }
    ears_.reset();
    if (rrs_ && settings_.roulette.mode == RouletteMode::Ears) {
        const Film& film = scene.sensor().film();
        ears_ = std::make_unique<ContinuationLearning>(guide_->selection_cells(), film.width(), film.height(),
                                                       settings_.ears);
    }
    if (learn) {
        if (given_prepass_ && !given_prepass_->selection.empty())
            guide_->set_selection(LearnedSelection::deserialize(given_prepass_->selection));
        else
            learn_selection(scene, context);
        // The pilot's counted costs bound guided splitting (roulette_splitting.h's adaptive budget).
        if (rrs_) rrs_->set_cost_ratio(guide_->selection().continuation_cost_ratio());
    }
}

void GuidedVolPathIntegrator::end_pass(const PassReport& pass) {
    if (ears_) ears_->end_pass();
    if (refining_.schedule) refine(pass);
}

void GuidedVolPathIntegrator::refine(const PassReport& pass) {
    const RefinementAction action = refining_.schedule->on_pass(pass);
    if (action == RefinementAction::Continue) return;
    const auto start = std::chrono::steady_clock::now();
    if (action == RefinementAction::Refine)
        refine_field(pass.seconds);
    else
        undo_refinement();
    refining_.schedule->done(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

PreprocessContext GuidedVolPathIntegrator::refinement_context() const {
    PreprocessContext context;
    context.seed = refining_.seed;
    context.progress = refining_.progress;
    context.cancel = refining_.cancel;
    return context;
}

// A further photon pass (new photons: the stream goes on from the last pass's), as many deposits as
// all passes before it (at most kRefineMaxDeposits), added to the field's statistics; then the
// field's medium fractions and everything built from the field, as after the pre-pass.
void GuidedVolPathIntegrator::refine_field(double job_seconds) {
    const int64_t deposits = std::min(refining_.deposits, GuidedVolPathSettings::kRefineMaxDeposits);
    const double remaining = refining_.time_budget > 0 ? std::max(0.0, refining_.time_budget - job_seconds) : 0.0;
    PhotonPassSettings ps = photon_settings(refining_.time_budget > 0 ? settings_.training_fraction * remaining : 0.0);
    ps.first_photon = refining_.photon_stream_next;
    ps.max_deposits = deposits;
    // The photons the deposits need at the passes' rate so far, with a margin (the cap stops the pass).
    ps.photons = std::max<int64_t>(1, int64_t(1.1 * double(refining_.photons_traced) * double(deposits) /
                                              double(std::max<int64_t>(refining_.deposits, 1))));
    const PreprocessContext context = refinement_context();
    PhotonPassResult photons = trace_photons(*refining_.scene, ps, context);
    refining_.photon_stream_next += ps.photons;
    if (photons.photons_traced == 0) return;
    refining_.photons_traced += photons.photons_traced;
    refining_.deposits += int64_t(photons.samples.size());
    const RefinementReport r = refining_.refinement->add(photons.samples, double(photons.photons_traced));
    std::vector<RadianceSample>().swap(photons.samples);
    refining_.previous_field = std::move(field_);
    field_ = refining_.refinement->field();
    measure_medium_fractions(*refining_.scene, refining_.seed + uint64_t(refining_.schedule->refinements() + 1), true);
    PreprocessContext build = context;
    build.seed = refining_.seed + 1000 + uint64_t(refining_.schedule->refinements());
    build_from_field(*refining_.scene, build, true);
    refining_.refined.leaf_splits += r.leaf_splits;
    refining_.refined.leaf_merges += r.leaf_merges;
    refining_.refined.lobe_splits += r.lobe_splits;
    refining_.refined.lobe_merges += r.lobe_merges;
}

// The last refinement made the render's noise worse (the schedule's judgement): its field goes, the
// one before it comes back (the refinement's statistics are no longer used: refining has ended).
void GuidedVolPathIntegrator::undo_refinement() {
    if (refining_.previous_field.empty()) return;
    field_ = std::move(refining_.previous_field);
    refining_.previous_field = GuidingField();
    PreprocessContext build = refinement_context();
    build.seed = refining_.seed + 2000;
    build_from_field(*refining_.scene, build, true);
    refining_.undone = true;
}

void GuidedVolPathIntegrator::load_or_train_field(const Scene& scene, const PreprocessContext& context) {
    bool photon_fluence = false;  // a photon-trained fluence still counts collisions per leaf volume
    if (given_prepass_) {
        field_ = given_prepass_->field;
    } else if (!settings_.load_field.empty()) {
        try {
            field_ = load_field(settings_.load_field);
        } catch (const FieldFormatError& e) {
            throw InputError(settings_.location, e.what());
        }
    } else {
        field_ = train_by_photons(scene, context, settings_.photons, context.time_limit);
        photon_fluence = true;
    }
    // Once per field, kept in its file (format v3): the photons' per-volume fluence is divided by
    // each leaf's medium share (collisions only happen inside media), and surface guiding and the
    // pixel estimate trust only leaves mostly filled by a medium (GuidingLeaf::mostly_medium). A
    // field of format v2 is measured here, its fluence left as it is.
    if (!field_.has_medium_fractions()) measure_medium_fractions(scene, context.seed, photon_fluence);
}

void GuidedVolPathIntegrator::measure_medium_fractions(const Scene& scene, uint64_t seed, bool photon_fluence) {
    if (!field_.empty())
        field_.set_medium_fractions(medium_fractions(scene, field_.tree(), kMediumFractionPoints, seed), photon_fluence);
}

PhotonPassSettings GuidedVolPathIntegrator::photon_settings(double time_limit) const {
    PhotonPassSettings ps;
    ps.photons = settings_.photons;
    ps.max_deposits = settings_.max_deposits;
    ps.focus = settings_.photon_focus;
    ps.max_depth = settings_.walk.max_depth;
    ps.rr_depth = settings_.walk.rr_depth;
    ps.time_limit = time_limit;
    return ps;
}

GuidingField GuidedVolPathIntegrator::train_by_photons(const Scene& scene, const PreprocessContext& context,
                                                       int64_t photon_count, double time_limit) {
    // Under a --time budget, training gets its share of the pre-pass's (PreprocessBudget).
    PhotonPassSettings ps = photon_settings(time_limit);
    ps.photons = photon_count;
    const PhotonPassResult photons = trace_photons(scene, ps, context);
    training_stats_ = {
        {"photons_traced", double(photons.photons_traced)},
        {"photons_pilot", double(photons.pilot_photons)},
        {"photons_depositing_fraction",
         photons.photons_traced > 0 ? double(photons.photons_depositing) / double(photons.photons_traced) : 0.0},
        {"photon_deposits", double(photons.samples.size())},
        {"photon_deposit_limited", photons.deposit_limited ? 1.0 : 0.0}};
    GuidingField field = GuidingField::build(guiding_bounds(scene), photons.samples, settings_.field);
    if (settings_.refine.passes > 0 && !field.empty() && photons.photons_traced > 0) {
        refining_.refinement = std::make_unique<FieldRefinement>(field, photons.samples, double(photons.photons_traced),
                                                        settings_.refinement);
        refining_.photon_stream_next = ps.photons;
        refining_.photons_traced = photons.photons_traced;
        refining_.deposits = int64_t(photons.samples.size());
    }
    return field;
}

// The pixel estimate I (docs/theory.md §9.5), once, from the finished field.
void GuidedVolPathIntegrator::make_pixel_estimate(const Scene& scene, const PreprocessContext& context) {
    const auto start = std::chrono::steady_clock::now();
    if (context.progress) {
        Progress p;
        p.phase = "pixel estimate";
        context.progress(p);
    }
    const CacheEstimator marcher(scene, field_);
    // Under a pre-pass deadline the estimate takes a share of the build stage's time, the pilot the rest.
    PixelEstimateSettings pixel = settings_.pixel;
    pixel.seconds = context.time_limit > 0 ? kPixelEstimateShare * context.time_limit : 0.0;
    pixel_estimate_ = PixelEstimate::raymarch(scene, field_, marcher, pixel, context);
    if (!settings_.save_pixel_estimate.empty()) {
        try {
            write_exr(settings_.save_pixel_estimate, pixel_estimate_.image());
        } catch (const std::exception& e) {
            throw InputError(settings_.location,
                             fmt::format("guided_volpath: cannot write the pixel estimate: {}", e.what()));
        }
    }
    pixel_estimate_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::erase_if(training_stats_, [](const auto& s) { return s.first == "pixel_estimate_rays"; });
    training_stats_.emplace_back("pixel_estimate_rays", double(pixel_estimate_.rays()));
}

// What the build stage's limit leaves the pilot after the pixel estimate (0: no limit).
double GuidedVolPathIntegrator::pilot_seconds(const PreprocessContext& context) const {
    if (!(context.time_limit > 0)) return 0.0;
    return std::max(1e-3, context.time_limit - pixel_estimate_seconds_);
}

// The learned selection's pilot (selection_pilot.h) with the configured mixtures, then its fit.
void GuidedVolPathIntegrator::learn_selection(const Scene& scene, const PreprocessContext& context) {
    const auto start = std::chrono::steady_clock::now();
    if (context.progress) {
        Progress p;
        p.phase = "selection pilot";
        context.progress(p);
    }
    const Film& film = scene.sensor().film();
    Learner learner(guide_->selection_cells(), film.width(), film.height());
    const uint64_t paths = run_selection_pilot(
        scene, SelectionPilotBudget{settings_.selection.pilot_spp, pilot_seconds(context)},
        [&](Point2f film_uv) { return pixel_estimate_.at(film_uv); },
        [&](Sampler& sampler, const Ray& ray, CellRecorder& recorder) {
            GuidedWalkPolicy policy(*guide_, nullptr, 0.f);
            return walk_.walk(scene, sampler, ray, &policy, &recorder);
        },
        context, learner);
    guide_->set_selection(LearnedSelection::fit(learner.total(), settings_.selection, guide_->configured_shares()));
    const LearnedSelection::Summary sum = guide_->selection().summary();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // A refinement learns the selection again: its figures replace the last ones.
    std::erase_if(training_stats_, [](const auto& s) { return s.first.rfind("selection_", 0) == 0; });
    training_stats_.insert(training_stats_.end(),
                           {{"selection_seconds", seconds},
                            {"selection_pilot_paths", double(paths)},
                            {"selection_cost_ratio", double(guide_->selection().continuation_cost_ratio())},
                            {"selection_distance_cells_guided", double(sum.guided[0])},
                            {"selection_distance_cells_unguided", double(sum.unguided[0])},
                            {"selection_direction_cells_guided", double(sum.guided[1])},
                            {"selection_direction_cells_unguided", double(sum.unguided[1])},
                            {"selection_surface_cells_guided", double(sum.guided[2])},
                            {"selection_surface_cells_unguided", double(sum.unguided[2])},
                            {"selection_distance_mean_share", sum.mean_share[0]},
                            {"selection_direction_mean_share", sum.mean_share[1]},
                            {"selection_surface_mean_share", sum.mean_share[2]}});
}

std::string GuidedVolPathIntegrator::prepass_state() const {
    return serialize_guided_prepass(field_, pixel_estimate_.image(),
                                    guide_ && !guide_->selection().empty() ? guide_->selection().serialize() : "",
                                    choice_.empty() ? "" : choice_.serialize());
}

void GuidedVolPathIntegrator::use_prepass_state(const std::string& bytes) {
    given_prepass_ = std::make_unique<GuidedPrepass>(deserialize_guided_prepass(bytes));
}

// The pixel estimate of a given pre-pass: exactly the one the training computed.
void GuidedVolPathIntegrator::use_given_pixel_estimate() {
    if (given_prepass_->pixel_estimate.pixels.empty())
        throw std::runtime_error("the given guided_volpath pre-pass has no pixel estimate (it was trained with rrs=standard)");
    pixel_estimate_ = PixelEstimate::from_image(given_prepass_->pixel_estimate, settings_.pixel.floor_fraction);
}

Color3 GuidedVolPathIntegrator::guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray, float pixel,
                                            PathRecorder* recorder, float camera_guided) const {
    if (!guide_) return walk_.walk(scene, sampler, ray, nullptr, recorder, &work_.local());
    GuidedWalkPolicy policy(*guide_, rrs_.get(), pixel, ears_ ? &ears_->snapshot() : nullptr);
    policy.set_camera_segment(camera_guided);
    return walk_.walk(scene, sampler, ray, &policy, recorder, &work_.local());
}

bool GuidedVolPathIntegrator::wants_camera_buffer() const {
    const DistanceGuiding d = settings_.guide.distance;
    return guide_ && d == DistanceGuiding::Vsp;
}

float GuidedVolPathIntegrator::camera_guided(const CameraRay& camera) const {
    if (!wants_camera_buffer()) return std::numeric_limits<float>::quiet_NaN();
    return pixel_estimate_.camera_scatter_probability(camera.film_uv);
}

Color3 GuidedVolPathIntegrator::render_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    const float pixel = rrs_ ? pixel_estimate_.at(camera.film_uv) : 0.f;
    if (!ears_) return guided_walk(scene, sampler, camera.ray, pixel, nullptr, camera_guided(camera));
    // The statistics keep X / I; the decisions compare with the pass's learned estimate I'.
    const long px = ears_->pixel(camera.film_uv);
    const float learned = ears_->snapshot().pixel_estimate(px, pixel);
    CellRecorder& learning = ears_->recorder();
    learning.begin(px, pixel);
    const Color3 L = guided_walk(scene, sampler, camera.ray, learned, &learning, camera_guided(camera));
    learning.end();
    return L;
}

Color3 GuidedVolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    // The tile's method, fixed before the first pass: both are unbiased, so the image is.
    if (choice_.at(camera.film_uv) == TileMethod::Volpath) return bounded_.walk(scene, sampler, camera.ray, nullptr);
    if (estimator_) {
        const CacheQuantity q =
            settings_.estimate == FieldEstimate::Incident ? CacheQuantity::Incident : CacheQuantity::Inscattered;
        return estimator_->estimate(camera.ray, scene.sensor().medium(), q, sampler);
    }
    return render_walk(scene, sampler, camera);
}

std::vector<std::pair<std::string, double>> GuidedVolPathIntegrator::statistics() const {
    std::vector<std::pair<std::string, double>> stats = training_stats_;
    WorkCounts work;
    for (const WorkCounts& w : work_) work += w;
    const auto named = named_work(work);
    stats.insert(stats.end(), named.begin(), named.end());
    if (refining_.schedule) {
        const auto named = refining_.schedule->named();
        stats.insert(stats.end(), named.begin(), named.end());
        stats.insert(stats.end(), {{"refine_leaf_splits", double(refining_.refined.leaf_splits)},
                                   {"refine_leaf_merges", double(refining_.refined.leaf_merges)},
                                   {"refine_lobe_splits", double(refining_.refined.lobe_splits)},
                                   {"refine_lobe_merges", double(refining_.refined.lobe_merges)},
                                   {"refine_deposits", double(refining_.deposits)},
                                   {"field_memory_bytes", double(refining_.refinement->memory_bytes())}});
        if (refining_.undone) stats.emplace_back("refine_undone", 1.0);
    }
    if (guide_) {
        const auto walk = guide_->stats().named();
        stats.insert(stats.end(), walk.begin(), walk.end());
        stats.emplace_back("leaf_groups", double(guide_->leaf_group_count()));
        const auto memory = guide_->memory_named();
        stats.insert(stats.end(), memory.begin(), memory.end());
    }
    if (rrs_) {
        const auto rr = rrs_->stats().named();
        stats.insert(stats.end(), rr.begin(), rr.end());
    }
    if (ears_) {
        const auto e = ears_->named();
        stats.insert(stats.end(), e.begin(), e.end());
    }
    return stats;
}

std::string GuidedVolPathIntegrator::to_string() const {
    return "guided_volpath[" + settings_.to_string() + "]";
}

}  // namespace volguide
