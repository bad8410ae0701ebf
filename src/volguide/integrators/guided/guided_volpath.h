#pragma once
// `guided_volpath`: volguide's zero-variance-based volume path guiding integrator (interface.md).
//
// preprocess() trains the guiding field by the photon pre-pass (docs/theory.md §5.2, §10.1) — first a
// coarse field from a fraction of the photons (training/training_stage.h) — or loads it (`load_field`),
// then prepares the guided decisions and the pixel estimate I (pixel_estimate.h: a raymarch through the
// field). The render is volpath's walk with GuidedWalkPolicy (walk/guided_walk_policy.h): the vertex
// objects make the distance (incremental / vsp) and direction (incident / product) decisions,
// GuidedContinuation the RR/splitting decisions after them (rrs=grr, grrs, ears), each with the share
// or rule the allocation (estimates/allocation.h) gives its cell. The allocation is learned while
// rendering: every pass's camera samples are recorded (estimates/learner.h), and after each pass the
// allocation is fitted again from all of them (end_pass); the coarse stage's first passes decide whether
// the full field is trained or the rest is rendered unguided. With refine_passes > 0 the field keeps
// learning from further photon passes between render passes (field_refinement.h,
// refinement_schedule.h). `estimate` renders the field's own inspection images instead.
// A pre-pass saved for other processes (`volguide train`, PreprocessContext::learn_in_prepass) learns
// the allocation in the pre-pass (learning passes of its own, estimates/learning_pass.h), and a render
// from a given pre-pass (`render --field`) keeps that allocation for every pass: all of a distributed
// render's chunks sample the same distributions. Under --time the pre-pass keeps within
// training_fraction of the budget (training/preprocess_budget.h). With distance=standard
// direction=phase rrs=standard it renders exactly what volpath renders.
#include <tbb/enumerable_thread_specific.h>

#include <limits>
#include <memory>
#include <string>

#include "volguide/guiding/field_refinement.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/estimates/cache_estimate.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"
#include "volguide/integrators/guided/estimates/cost_model.h"
#include "volguide/integrators/guided/estimates/learner.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/integrators/guided/guided_volpath_settings.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/integrators/guided/training/preprocess_budget.h"
#include "volguide/integrators/guided/training/refinement_state.h"
#include "volguide/integrators/guided/training/training_stage.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/volpath.h"

namespace volguide {

class GuidedVolPathIntegrator final : public Integrator {
public:
    explicit GuidedVolPathIntegrator(const Properties& props);
    // Guided RR/splitting compares with the pixel estimate at the camera ray's film position.
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    // The pass's samples join the allocation's statistics and the allocation is fitted again; the
    // coarse stage may end here (training/training_stage.h); rrs=ears: the pass's statistics join the
    // learned ones. With refine_passes > 0, the refinement schedule (refinement_schedule.h) may add a
    // further photon pass to the field here, or undo the last one.
    void end_pass(const PassReport& pass) override;
    std::vector<std::pair<std::string, double>> statistics() const override;
    std::string to_string() const override;
    // The field, the pixel estimate and the allocation (guided_prepass.h); use_prepass_state() makes
    // preprocess() take them instead of training (and of load_field).
    bool has_prepass_state() const override { return true; }
    std::string prepass_state() const override;
    void use_prepass_state(const std::string& bytes) override;

    // Checkpoints (guided_volpath_state.cpp): everything end_pass() changed since preprocess() — the
    // training stage and its counters (with the coarse stage's deposits), the full field when the render
    // trained it, the learner's statistics, the allocation, the recording rule — so that a resumed render
    // (preprocess() again, then restore_render_state) renders the same passes bit for bit. Not for
    // rrs=ears or refine_passes > 0 (render_state_unsupported).
    std::string render_state() const override;
    void restore_render_state(const std::string& bytes) override;
    std::string render_state_unsupported() const override;

    const GuidedVolPathSettings& settings() const { return settings_; }
    // The trained (or loaded) field; empty before preprocess().
    const GuidingField& field() const { return field_; }
    // The pixel estimate of guided RR/splitting; empty with rrs=standard.
    const PixelEstimate& pixel_estimate() const { return pixel_estimate_; }
    // The allocation the next pass renders with (empty: the configured mixtures everywhere).
    const Allocation& allocation() const;
    // Whether the render has become the unguided walk (nothing guided paid, training_stage.h).
    bool stopped() const { return training_.stage == TrainingStage::Stopped; }

private:
    // What a guided walk of a camera ray is given besides the ray: the pixel estimate I of its pixel,
    // its recorder (null: none), distance=vsp's P_G of its camera segment (NaN: none;
    // GuidedWalkPolicy::set_camera_segment), whether it is recorded for the allocation.
    struct WalkInputs {
        float pixel = 0.f;
        PathRecorder* recorder = nullptr;
        float camera_guided = std::numeric_limits<float>::quiet_NaN();
        bool learning = false;
    };
    Color3 guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray, const WalkInputs& in) const;
    // Whether distance=vsp's camera segments read the pixel estimate's camera-ray buffer, and its value
    // for a camera sample (NaN: none).
    bool wants_camera_buffer() const;
    float camera_guided(const CameraRay& camera) const;
    // Li's guided walk of a camera sample: recorded by the allocation's learner (or rrs=ears') while it
    // learns.
    Color3 render_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera) const;
    Color3 learning_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera, float pixel) const;
    // Whether the camera sample of `sampler` is recorded for the allocation (all of them early on, then
    // a fixed subset).
    bool recorded(const Sampler& sampler) const;
    // Whether the camera sample of `sampler` is a control sample (the unguided walk, measured for the
    // gain while the training can still stop), and its walk.
    bool control(const Sampler& sampler) const;
    Color3 control_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera) const;
    Color3 ears_walk(const Scene& scene, Sampler& sampler, const CameraRay& camera, float pixel) const;

    // preprocess()'s steps: the field (given, loaded, or the coarse stage's) with its leaves' medium
    // fractions, then everything built from it.
    void load_or_train_field(const Scene& scene, const PreprocessContext& context, const PreprocessBudget& budget);
    // Each leaf's medium share (medium_occupancy.h) into field_; photon_fluence: divide its fluence by it.
    void measure_medium_fractions(const Scene& scene, uint64_t seed, bool photon_fluence);
    PhotonPassResult trace_photon_pass(const Scene& scene, const PreprocessContext& context, int64_t first,
                                       int64_t photons, double time_limit);
    // The field of `photons` (their weights for photons_traced photons alone) and the refinement's
    // statistics when refining.
    GuidingField field_of(const Scene& scene, const std::vector<RadianceSample>& photons, int64_t photons_traced,
                          int64_t stream_next);
    void record_photon_stats(const PhotonPassResult& photons);
    void make_pixel_estimate(const Scene& scene, const PreprocessContext& context);
    void use_given_pixel_estimate();
    // The guide, the pixel estimate, RR/splitting and the allocation's learner of field_ (preprocess(),
    // a new stage, every refinement; `update` true: the RR/splitting statistics carry on).
    void build_from_field(const Scene& scene, const PreprocessContext& context, bool update);
    void record_field_stats();
    void save_trained_field() const;

    // The allocation's learning: whether walks learn it, the fit after a pass, the coarse stage's
    // decision and the full stage's training; the learning passes of a saved pre-pass.
    bool learns() const;
    void learn_from_pass(int spp_done, double job_seconds);
    void fit_allocation();
    void decide_training(double job_seconds);
    void stop_guiding(double job_seconds);
    void train_full_field(double time_limit);
    void learn_in_prepass(const Scene& scene, const PreprocessContext& context, const PreprocessBudget& budget);

    // Refinement during the render (issue 39): what the schedule asks after a pass; a further photon
    // pass into the field; the field before the last refinement again.
    void refine(const PassReport& pass);
    void refine_field(double job_seconds);
    void undo_refinement();
    PhotonPassSettings photon_settings(double time_limit) const;
    PreprocessContext refinement_context() const;

    // restore_render_state()'s steps: the full field the render had trained after `full_from` samples
    // per pixel, with everything built from it; the learner's statistics and the allocation.
    void restore_full_field(const std::string& field_bytes, int full_from);
    void restore_learning(const std::string& statistics, const std::string& pixels, const std::string& allocation);

    GuidedVolPathSettings settings_;
    VolPathIntegrator walk_;
    CostModel costs_ = CostModel::fitted();
    GuidingField field_;
    std::unique_ptr<CacheEstimator> estimator_;  // estimate != none
    std::unique_ptr<WalkGuide> guide_;           // a guided distance, direction or RR decision
    std::unique_ptr<RouletteSplitting> rrs_;     // rrs != standard
    // rrs=ears: what the render's passes learn (per field: a refinement starts it afresh).
    std::unique_ptr<ContinuationLearning> ears_;
    // The allocation's learner (per field); null when the allocation is fixed (a given pre-pass,
    // allocation=false, ears) or the render has become unguided.
    std::unique_ptr<Learner> learner_;
    bool record_all_ = true;
    StagedTraining training_;
    int spp_done_ = 0;  // the render's samples per pixel so far (the last end_pass's)
    PixelEstimate pixel_estimate_;
    std::unique_ptr<GuidedPrepass> given_prepass_;  // use_prepass_state(): no training
    RefinementState refining_;                      // refine_passes > 0; the scene and context for all stages
    double pixel_estimate_seconds_ = 0;
    std::vector<std::pair<std::string, double>> training_stats_;  // of the last preprocess()
    // The render walks' counted work (volpath/work.h), since the last preprocess().
    mutable tbb::enumerable_thread_specific<WorkCounts> work_;
};

}  // namespace volguide
