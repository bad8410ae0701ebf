#pragma once
// `guided_volpath`: volguide's zero-variance-based volume path guiding integrator (interface.md).
//
// preprocess() trains the guiding field by the photon pre-pass (docs/theory.md §5.2, §10.1), or loads it
// (`load_field`), then prepares the guided decisions and, for guided RR/splitting and the learned
// selection, the pixel estimate I (pixel_estimate.h: a raymarch through the field), then learns the
// selection from a pilot (selection_pilot.h, learned_selection.h: per leaf the guided share of each
// decision; `selection_spp`, default 2). The render is volpath's walk with GuidedWalkPolicy
// (walk/guided_walk_policy.h): the vertex objects make the distance (incremental / vsp) and direction
// (incident / product) decisions, GuidedContinuation the RR/splitting decisions after them (rrs=grr,
// grrs, ears). With refine_passes > 0 the field keeps learning from further photon passes between
// render passes (field_refinement.h, refinement_schedule.h). `estimate` renders the field's own
// inspection images instead.
// With method_choice (the default) the pre-pass is staged (issue 55): probes of volpath rr_rule=bounded,
// then a coarse field and the guided configuration's probes on it; when every tile is volpath's
// (estimates/method_choice.h) training stops there and the render is bounded volpath's; otherwise the full
// field is trained, the guided probes repeated with it, and the final map decides per 16 x 16 tile which
// method renders it (Li dispatches on the camera ray's film position). Under --time the whole pre-pass
// keeps within training_fraction of the budget (training/preprocess_budget.h). With distance=standard direction=phase rrs=standard it renders exactly
// what volpath renders.
#include <tbb/enumerable_thread_specific.h>

#include <limits>
#include <memory>
#include <string>

#include "volguide/guiding/field_refinement.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/estimates/cache_estimate.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"
#include "volguide/integrators/guided/estimates/method_choice.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"
#include "volguide/integrators/guided/guided_volpath_settings.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/integrators/guided/training/preprocess_budget.h"
#include "volguide/integrators/guided/training/refinement_state.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/guided/walk/walk_guide.h"

namespace volguide {

class GuidedVolPathIntegrator final : public Integrator {
public:
    explicit GuidedVolPathIntegrator(const Properties& props);
    // Guided RR/splitting compares with the pixel estimate at the camera ray's film position.
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    // rrs=ears: the pass's statistics join the learned ones. With refine_passes > 0, the refinement schedule (refinement_schedule.h) may add a further photon
    // pass to the field here, or undo the last one.
    void end_pass(const PassReport& pass) override;
    std::vector<std::pair<std::string, double>> statistics() const override;
    Image method_map() const override { return choice_.empty() ? Image() : choice_.image(); }
    std::string to_string() const override;
    // The field and the pixel estimate (guided_prepass.h); use_prepass_state() makes preprocess()
    // take them instead of training (and of load_field).
    bool has_prepass_state() const override { return true; }
    std::string prepass_state() const override;
    void use_prepass_state(const std::string& bytes) override;

    const GuidedVolPathSettings& settings() const { return settings_; }
    // The trained (or loaded) field; empty before preprocess().
    const GuidingField& field() const { return field_; }
    // The pixel estimate of guided RR/splitting; empty with rrs=standard.
    const PixelEstimate& pixel_estimate() const { return pixel_estimate_; }
    // The per-tile method choice of the last preprocess() (empty: every tile guided).
    const ChoiceMap& choice_map() const { return choice_; }

private:
    GuidedVolPathSettings settings_;
    VolPathIntegrator walk_;
    VolPathIntegrator bounded_;  // volpath with rr_rule=bounded: the method choice's other method
    ChoiceMap choice_;
    double probe_seconds_[2] = {0, 0};  // the last probes' CPU time per TileMethod (statistics only)
    GuidingField field_;
    std::unique_ptr<CacheEstimator> estimator_;  // estimate != none
    std::unique_ptr<WalkGuide> guide_;           // a guided distance, direction or RR decision
    std::unique_ptr<RouletteSplitting> rrs_;     // rrs != standard
    // rrs=ears: what the render's passes learn (per field: a refinement starts it afresh).
    std::unique_ptr<ContinuationLearning> ears_;
    PixelEstimate pixel_estimate_;
    std::unique_ptr<GuidedPrepass> given_prepass_;  // use_prepass_state(): no training
    // The guided walk along ray, with guided RR/splitting (when rrs_) against the pixel value I;
    // `recorder` (null: none) records it.
    // `camera_guided`: distance=vsp's P_G for the camera segment (NaN: none; GuidedWalkPolicy::set_camera_segment).
    Color3 guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray, float pixel,
                       PathRecorder* recorder = nullptr,
                       float camera_guided = std::numeric_limits<float>::quiet_NaN()) const;
    // Whether distance=vsp's camera segments read the pixel estimate's camera-ray buffer, and its value
    // for a camera sample (NaN: none).
    bool wants_camera_buffer() const;
    float camera_guided(const CameraRay& camera) const;
    // Li's guided walk of a camera sample, recorded with rrs=ears by the learner's recorder.
    Color3 render_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera) const;
    // preprocess()'s steps: the field (loaded or trained) with its leaves' medium fractions, then
    // the pixel estimate I of guided RR/splitting.
    void load_or_train_field(const Scene& scene, const PreprocessContext& context);
    // The staged pre-pass with the method choice (see the file comment); its steps.
    bool chooses() const;
    void staged_training(const Scene& scene, const PreprocessContext& context, const PreprocessBudget& budget);
    void train_stage(const Scene& scene, const PreprocessContext& context, int64_t photons, double time_limit);
    void build_stage(const Scene& scene, const PreprocessContext& context, double time_limit);
    // `rounds` probe rounds of `method` (under a time budget: fewer, within `time_limit`); the rounds done.
    int run_probes(const Scene& scene, const PreprocessContext& context, ChoiceProbes& probes, TileMethod method,
                   int rounds, double time_limit);
    int probe_rounds(const PreprocessContext& context) const;
    ChoiceMap decide_choice(const Scene& scene, const ChoiceProbes& probes) const;
    void record_choice_stats(int stage, const ChoiceProbes& probes, int volpath_rounds, int guided_rounds,
                             double seconds);
    // Each leaf's medium share (medium_occupancy.h) into field_; photon_fluence: divide its fluence by it.
    void measure_medium_fractions(const Scene& scene, uint64_t seed, bool photon_fluence);
    GuidingField train_by_photons(const Scene& scene, const PreprocessContext& context, int64_t photons,
                                  double time_limit);
    void make_pixel_estimate(const Scene& scene, const PreprocessContext& context);
    void use_given_pixel_estimate();
    void learn_selection(const Scene& scene, const PreprocessContext& context);
    double pilot_seconds(const PreprocessContext& context) const;
    // The guide, the pixel estimate, RR/splitting and the learned selection of field_ (preprocess(),
    // and every refinement, `update` true: the RR/splitting statistics carry on).
    void build_from_field(const Scene& scene, const PreprocessContext& context, bool update);
    void record_field_stats();
    // Refinement during the render (issue 39): what the schedule asks after a pass; a further photon
    // pass into the field; the field before the last refinement again.
    void refine(const PassReport& pass);
    void refine_field(double job_seconds);
    void undo_refinement();
    PhotonPassSettings photon_settings(double time_limit) const;
    PreprocessContext refinement_context() const;
    RefinementState refining_;  // refine_passes > 0
    // The render walks' counted work (volpath/work.h), since the last preprocess().
    mutable tbb::enumerable_thread_specific<WorkCounts> work_;
    double pixel_estimate_seconds_ = 0;
    std::vector<std::pair<std::string, double>> training_stats_;  // of the last preprocess()
};

}  // namespace volguide
