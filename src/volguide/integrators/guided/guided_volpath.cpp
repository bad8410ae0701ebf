#include "volguide/integrators/guided/guided_volpath.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "volguide/core/cpu_time.h"
#include "volguide/core/log.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/estimates/learning_pass.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/integrators/guided/walk/guided_walk_policy.h"
#include "volguide/render/image_io.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

// The pixel estimate's share of the build stage's time limit.
constexpr double kPixelEstimateShare = 0.4;
// The photons' share of the pre-pass's time (the rest: the field's fit, the pixel estimate), and the
// coarse stage's share of that.
constexpr double kPhotonShare = 0.6;
constexpr double kCoarseShare = 0.25;
// Recording a camera sample for the allocation costs about what a guided decision does (bench/RESULTS.md,
// issue 59): after the first kRecordAllSpp samples per pixel, one camera sample in kRecordEvery is
// recorded (chosen by a hash of its stream: the same samples for any thread count).
constexpr int kRecordAllSpp = 8;
constexpr uint64_t kRecordEvery = 4;
constexpr uint64_t kRecordSalt = 0x5eed0f1ea4ull;
// While the full stage can still stop (its first kConfirmSpp), one camera sample in kControlEvery is a
// control sample: the unguided walk, its value and cost measured for the gain (Allocation::fit); every
// such sample is an unbiased sample of the pixel like the others. The coarse stage decides on the fit's
// prediction: a few early samples' tails make the measured gain at 4 spp swing by 100x between seeds
// (bench/RESULTS.md, issue 59).
constexpr uint64_t kControlEvery = 8;
constexpr uint64_t kControlSalt = 0xc0417013ull;
// A saved pre-pass's learning passes (learn_in_prepass): kLearningSpp samples per pilot pixel each, the
// allocation fitted after each; kCoarseRounds on the coarse field before the stage's decision, then
// kFullRounds on the full one.
constexpr int kLearningSpp = 2;
constexpr int kCoarseRounds = 2;
constexpr int kFullRounds = 4;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

GuidedVolPathIntegrator::GuidedVolPathIntegrator(const Properties& props)
    : settings_(GuidedVolPathSettings::from(props)), walk_(settings_.walk) {}

void GuidedVolPathIntegrator::preprocess(const Scene& scene, const PreprocessContext& context) {
    training_stats_.clear();
    work_.clear();
    refining_ = RefinementState{};
    refining_.scene = &scene;
    refining_.seed = context.seed;
    refining_.time_budget = context.time_budget;
    refining_.progress = context.progress;
    refining_.cancel = context.cancel;
    training_ = StagedTraining{};
    spp_done_ = 0;
    const PreprocessBudget budget(context.time_budget, settings_.training_fraction);
    walk_.preprocess(scene, context);
    if (settings_.refine.passes > 0 && given_prepass_)
        throw InputError(settings_.location, "guided_volpath: refine_passes cannot refine a given pre-pass (render "
                                             "--field): it keeps the statistics of the photons it was trained from");
    const auto training_start = std::chrono::steady_clock::now();
    load_or_train_field(scene, context, budget);
    refining_.training_seconds = seconds_since(training_start);
    PreprocessContext build = context;
    build.time_limit = budget.limit(1.0);
    build_from_field(scene, build, false);
    training_.seconds = seconds_since(training_start);
    if (context.learn_in_prepass && learner_) learn_in_prepass(scene, context, budget);
    if (budget.limited()) training_stats_.emplace_back("preprocess_limit_seconds", budget.total());
    if (refining_.refinement)
        refining_.schedule = std::make_unique<RefinementSchedule>(settings_.refine, context.time_budget,
                                                                  refining_.training_seconds);
    save_trained_field();
}

// save_field: the pre-pass's field, written again when the full stage replaces the coarse one.
void GuidedVolPathIntegrator::save_trained_field() const {
    if (settings_.save_field.empty()) return;
    try {
        save_field(settings_.save_field, field_);
    } catch (const FieldFormatError& e) {
        throw InputError(settings_.location, e.what());
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

bool GuidedVolPathIntegrator::learns() const {
    const bool given = given_prepass_ != nullptr;
    return guide_ && !estimator_ && settings_.learn_allocation && settings_.roulette.mode != RouletteMode::Ears &&
           !given;
}

void GuidedVolPathIntegrator::build_from_field(const Scene& scene, const PreprocessContext& context, bool update) {
    record_field_stats();
    estimator_.reset();
    if (settings_.estimate != FieldEstimate::None) estimator_ = std::make_unique<CacheEstimator>(scene, field_);
    guide_.reset();
    learner_.reset();
    if (!update) rrs_.reset();
    pixel_estimate_ = PixelEstimate();
    pixel_estimate_seconds_ = 0;
    if (settings_.guide.distance != DistanceGuiding::Standard ||
        settings_.guide.direction != DirectionGuiding::Phase || settings_.roulette.mode != RouletteMode::Standard)
        guide_ = std::make_unique<WalkGuide>(scene, field_, settings_.guide);
    // The allocation's learning compares every camera sample with the pixel estimate too.
    const bool learn = learns();
    const bool given_allocation = guide_ && given_prepass_ && !given_prepass_->allocation.empty();
    if ((settings_.roulette.mode != RouletteMode::Standard || learn || given_allocation) && !estimator_) {
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
    const Film& film = scene.sensor().film();
    if (rrs_ && settings_.roulette.mode == RouletteMode::Ears)
        ears_ = std::make_unique<ContinuationLearning>(guide_->selection_cells(), film.width(), film.height(),
                                                       settings_.ears, costs_);
    if (given_allocation) {
        Allocation a = Allocation::deserialize(given_prepass_->allocation);
        if (a.cells() != guide_->selection_cells())
            throw std::runtime_error("the given guided_volpath pre-pass's allocation is of another field");
        if (a.off()) training_.stage = TrainingStage::Stopped;
        if (rrs_) rrs_->set_cost_ratio(a.continuation_cost_ratio());
        guide_->set_allocation(std::move(a));
    } else if (learn) {
        learner_ = std::make_unique<Learner>(guide_->selection_cells(), film.width(), film.height(), costs_);
        record_all_ = true;
        guide_->set_allocation(Allocation::exploring(guide_->selection_cells()));
    }
}

void GuidedVolPathIntegrator::end_pass(const PassReport& pass) {
    spp_done_ = pass.spp_done;
    if (ears_) ears_->end_pass();
    if (learner_) learn_from_pass(pass.spp_done, pass.seconds);
    if (refining_.schedule) refine(pass);
}

// The pass's samples join the statistics; the allocation is fitted again from all of them; the coarse
// stage's passes end in its decision.
bool GuidedVolPathIntegrator::recorded(const Sampler& sampler) const {
    return record_all_ || mix64(sampler.key() ^ kRecordSalt) % kRecordEvery == 0;
}

bool GuidedVolPathIntegrator::control(const Sampler& sampler) const {
    const bool confirming =
        training_.stage == TrainingStage::Full && spp_done_ < training_.full_from + StagedTraining::kConfirmSpp;
    return confirming && mix64(sampler.key() ^ kControlSalt) % kControlEvery == 0;
}

void GuidedVolPathIntegrator::learn_from_pass(int spp_done, double job_seconds) {
    learner_->end_pass();
    record_all_ = spp_done < kRecordAllSpp;
    fit_allocation();
    if (training_.stage == TrainingStage::Coarse && spp_done >= StagedTraining::kDecideSpp) {
        decide_training(job_seconds);
    } else if (training_.stage == TrainingStage::Full && spp_done >= training_.full_from + StagedTraining::kConfirmSpp &&
               guide_->allocation().gain() < StagedTraining::kPaysGain) {
        stop_guiding(job_seconds);  // the full field did not make it pay either
    }
}

void GuidedVolPathIntegrator::fit_allocation() {
    AllocationSettings settings = settings_.allocation;
    settings.recorded_fraction = 1.0 / double(kRecordEvery);  // what the rest of the render records
    settings.mean_square = learner_->pixels().mean_square();
    guide_->set_allocation(Allocation::fit(learner_->total(), field_.tree(), settings));
    // The measured costs bound guided splitting (roulette_splitting.h's adaptive budget).
    if (rrs_) rrs_->set_cost_ratio(guide_->allocation().continuation_cost_ratio());
}

// The coarse stage's decision (training_stage.h): the rest of the render unguided, or the full field.
void GuidedVolPathIntegrator::decide_training(double job_seconds) {
    const double gain = guide_->allocation().gain();
    training_stats_.emplace_back("allocation_coarse_gain", gain);
    training_stats_.emplace_back("allocation_coarse_predicted_gain", guide_->allocation().summary().predicted_gain);
    if (gain < StagedTraining::kPaysGain) {
        stop_guiding(job_seconds);
        return;
    }
    double limit = 0.0;  // the pre-pass's time budget, what the coarse stage left of it
    if (refining_.time_budget > 0)
        limit = std::max(1e-3, settings_.training_fraction * refining_.time_budget - training_.seconds);
    train_full_field(limit);
}

// Nothing pays: the rest of the render is the unguided walk, nothing recorded, looked up or built.
void GuidedVolPathIntegrator::stop_guiding(double job_seconds) {
    training_.stage = TrainingStage::Stopped;
    learner_.reset();
    std::vector<RadianceSample>().swap(training_.deposits);
    training_stats_.emplace_back("training_stopped_at_seconds", job_seconds);
}

// The rest of the photons, the field of all of them (the coarse stage's and these, each weighted for
// its share of the photons), and everything built from it; the allocation is learned again on it.
void GuidedVolPathIntegrator::train_full_field(double time_limit) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    const Scene& scene = *refining_.scene;
    const PreprocessContext context = refinement_context();
    PhotonPassResult more =
        trace_photon_pass(scene, context, training_.photon_stream_next,
                          std::max<int64_t>(1, settings_.photons - training_.photons_traced), kPhotonShare * time_limit);
    const double total = double(training_.photons_traced + more.photons_traced);
    std::vector<RadianceSample> photons = std::move(training_.deposits);
    const float coarse_share = float(double(training_.photons_traced) / total);
    const float full_share = float(double(more.photons_traced) / total);
    for (RadianceSample& s : photons) s.weight *= coarse_share;
    for (RadianceSample& s : more.samples) s.weight *= full_share;
    photons.insert(photons.end(), more.samples.begin(), more.samples.end());
    record_photon_stats(more);  // before its deposits go (photon_deposits)
    std::vector<RadianceSample>().swap(more.samples);
    training_stats_.emplace_back("photons_traced_full_stage", double(more.photons_traced));
    field_ = field_of(scene, photons, int64_t(total), training_.photon_stream_next + more.photons_traced);
    std::vector<RadianceSample>().swap(photons);
    measure_medium_fractions(scene, refining_.seed + 1, true);
    PreprocessContext build = context;
    build.seed = refining_.seed + 3000;
    build.time_limit = time_limit > 0 ? std::max(1e-3, time_limit - seconds_since(start)) : 0.0;
    build_from_field(scene, build, true);
    training_.stage = TrainingStage::Full;
    training_.full_from = spp_done_;
    save_trained_field();
    training_.seconds += seconds_since(start);
    // The full stage runs between passes: the render's time includes it (bench/fit_cost_model.py takes
    // its CPU time out of the passes').
    training_stats_.emplace_back("training_full_stage_seconds", seconds_since(start));
    training_stats_.emplace_back("training_full_stage_cpu_seconds", process_cpu_seconds() - cpu_start);
}

// A saved pre-pass (volguide train): the allocation learned from learning passes of its own, then
// frozen — every process rendering from the pre-pass samples the same distributions.
void GuidedVolPathIntegrator::learn_in_prepass(const Scene& scene, const PreprocessContext& context,
                                               const PreprocessBudget& budget) {
    if (context.progress) {
        Progress p;
        p.phase = "allocation";
        context.progress(p);
    }
    const auto walk = [&](Sampler& sampler, const CameraRay& camera, CellRecorder& recorder) {
        GuidedWalkPolicy policy(*guide_, rrs_.get(), pixel_estimate_.at(camera.film_uv), nullptr, true);
        policy.set_camera_segment(camera_guided(camera));
        return walk_.walk(scene, sampler, camera.ray, &policy, &recorder);
    };
    int first = 0;
    for (int round = 0; learner_ && round < kCoarseRounds + kFullRounds; ++round) {
        const LearningPassBudget pass{first, kLearningSpp, budget.limit(0.25)};
        run_learning_pass(
            scene, pass, [&](Point2f film_uv) { return pixel_estimate_.metric_scale(film_uv); }, walk, context,
            *learner_);
        first += kLearningSpp;
        fit_allocation();
        if (training_.stage == TrainingStage::Coarse && round + 1 == kCoarseRounds) decide_training(0.0);
    }
    if (training_.stage == TrainingStage::Stopped) guide_->set_allocation(Allocation::unguided(guide_->selection_cells()));
    learner_.reset();  // frozen
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

void GuidedVolPathIntegrator::load_or_train_field(const Scene& scene, const PreprocessContext& context,
                                                  const PreprocessBudget& budget) {
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
        // The coarse stage when the allocation will decide whether more training pays (not with a
        // refinement, which keeps its own photons' statistics, nor for the field's inspection images).
        const bool staged = settings_.learn_allocation && settings_.refine.passes == 0 &&
                            settings_.estimate == FieldEstimate::None && settings_.roulette.mode != RouletteMode::Ears;
        const int64_t photons = staged ? std::max<int64_t>(1, settings_.photons / StagedTraining::kCoarseDivisor)
                                       : settings_.photons;
        const double limit = budget.limit(staged ? kPhotonShare * kCoarseShare : kPhotonShare);
        PhotonPassResult traced = trace_photon_pass(scene, context, 0, photons, limit);
        record_photon_stats(traced);
        if (staged) {
            training_.stage = TrainingStage::Coarse;
            training_.deposits = traced.samples;
            training_.photons_traced = traced.photons_traced;
            training_.photon_stream_next = photons;
        }
        field_ = field_of(scene, traced.samples, traced.photons_traced, photons);
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

// Photons [first, first + photons) of the photon stream (a coarse stage's deposit cap is its share of
// max_deposits).
PhotonPassResult GuidedVolPathIntegrator::trace_photon_pass(const Scene& scene, const PreprocessContext& context,
                                                            int64_t first, int64_t photons, double time_limit) {
    PhotonPassSettings ps = photon_settings(time_limit);
    ps.first_photon = first;
    ps.photons = photons;
    if (ps.max_deposits > 0)
        ps.max_deposits = std::max<int64_t>(1, int64_t(double(ps.max_deposits) * double(photons) /
                                                       double(std::max<int64_t>(settings_.photons, 1))));
    return trace_photons(scene, ps, context);
}

void GuidedVolPathIntegrator::record_photon_stats(const PhotonPassResult& photons) {
    std::erase_if(training_stats_, [](const auto& s) { return s.first.rfind("photon", 0) == 0; });
    training_stats_.insert(
        training_stats_.end(),
        {{"photons_traced", double(photons.photons_traced)},
         {"photons_pilot", double(photons.pilot_photons)},
         {"photons_depositing_fraction",
          photons.photons_traced > 0 ? double(photons.photons_depositing) / double(photons.photons_traced) : 0.0},
         {"photon_deposits", double(photons.samples.size())},
         {"photon_deposit_limited", photons.deposit_limited ? 1.0 : 0.0}});
}

GuidingField GuidedVolPathIntegrator::field_of(const Scene& scene, const std::vector<RadianceSample>& photons,
                                               int64_t photons_traced, int64_t stream_next) {
    GuidingField field = GuidingField::build(guiding_bounds(scene), photons, settings_.field);
    if (settings_.refine.passes > 0 && !field.empty() && photons_traced > 0) {
        refining_.refinement =
            std::make_unique<FieldRefinement>(field, photons, double(photons_traced), settings_.refinement);
        refining_.photon_stream_next = stream_next;
        refining_.photons_traced = photons_traced;
        refining_.deposits = int64_t(photons.size());
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

std::string GuidedVolPathIntegrator::prepass_state() const {
    const bool allocated = guide_ && !guide_->allocation().empty();
    return serialize_guided_prepass(field_, pixel_estimate_.image(), allocated ? guide_->allocation().serialize() : "");
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

const Allocation& GuidedVolPathIntegrator::allocation() const {
    static const Allocation none;
    return guide_ ? guide_->allocation() : none;
}

Color3 GuidedVolPathIntegrator::guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray,
                                            const WalkInputs& in) const {
    if (!guide_) return walk_.walk(scene, sampler, ray, nullptr, in.recorder, &work_.local());
    GuidedWalkPolicy policy(*guide_, rrs_.get(), in.pixel, ears_ ? &ears_->snapshot() : nullptr, in.learning);
    policy.set_camera_segment(in.camera_guided);
    return walk_.walk(scene, sampler, ray, &policy, in.recorder, &work_.local());
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
    // Nothing guided paid: the unguided walk (bounded volpath's), nothing looked up.
    if (stopped()) return walk_.walk(scene, sampler, camera.ray, nullptr, nullptr, &work_.local());
    const float pixel = rrs_ || learner_ ? pixel_estimate_.at(camera.film_uv) : 0.f;
    if (ears_) return ears_walk(scene, sampler, camera, pixel);
    if (learner_ && control(sampler)) return control_walk(scene, sampler, camera);
    if (learner_ && recorded(sampler)) return learning_walk(scene, sampler, camera, pixel);
    return guided_walk(scene, sampler, camera.ray, {pixel, nullptr, camera_guided(camera), false});
}

Color3 GuidedVolPathIntegrator::learning_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera,
                                              float pixel) const {
    CellRecorder& recorder = learner_->recorder();
    recorder.begin(learner_->pixel(camera.film_uv), pixel_estimate_.metric_scale(camera.film_uv));
    const Color3 L = guided_walk(scene, sampler, camera.ray, {pixel, &recorder, camera_guided(camera), true});
    recorder.end();
    return L;
}

Color3 GuidedVolPathIntegrator::control_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
    CellRecorder& recorder = learner_->recorder();
    recorder.begin(learner_->pixel(camera.film_uv), pixel_estimate_.metric_scale(camera.film_uv), true);
    const Color3 L = walk_.walk(scene, sampler, camera.ray, nullptr, &recorder, &work_.local());
    recorder.end();
    return L;
}

// rrs=ears: the statistics keep X / I; the decisions compare with the pass's learned estimate I'.
Color3 GuidedVolPathIntegrator::ears_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera,
                                          float pixel) const {
    const long px = ears_->pixel(camera.film_uv);
    const float learned = ears_->snapshot().pixel_estimate(px, pixel);
    CellRecorder& learning = ears_->recorder();
    learning.begin(px, pixel);
    const Color3 L = guided_walk(scene, sampler, camera.ray, {learned, &learning, camera_guided(camera), false});
    learning.end();
    return L;
}

Color3 GuidedVolPathIntegrator::Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const {
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
    stats.emplace_back("training_stage", double(int(training_.stage)));
    if (refining_.schedule) {
        const auto refined = refining_.schedule->named();
        stats.insert(stats.end(), refined.begin(), refined.end());
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
        if (!guide_->allocation().empty()) {
            const auto allocation = guide_->allocation().named();
            stats.insert(stats.end(), allocation.begin(), allocation.end());
        }
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
