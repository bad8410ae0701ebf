#pragma once
// `guided_volpath`: volguide's zero-variance-based volume path guiding integrator (interface.md).
//
// preprocess() trains the guiding field, by the photon pre-pass (training=photons, theory.md §5.2,
// §10.1) or PPG-style from camera paths (training=progressive, §10.2, progressive_training.h:
// training_iterations iterations of 2^k spp with volpath's walk, field rebuilt after each), or
// loads it (`load_field`), then prepares the guided decisions and, for guided RR/splitting, the
// pixel estimate I (pixel_estimate.h: raymarch through the field, or render a few guided spp and
// filter them). The render is volpath's walk with a WalkGuide (walk_guide.h) making the distance
// (incremental / tabulated) and direction (incident / product) decisions and RouletteSplitting
// (roulette_splitting.h) the RR/splitting decisions after them (rrs=grr/grrs). `estimate` renders
// the field's own inspection images instead. With distance=standard direction=phase rrs=standard
// it renders exactly what volpath renders.
#include <memory>
#include <string>

#include "volguide/integrators/cache_estimate.h"
#include "volguide/core/properties.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/volpath.h"
#include "volguide/integrators/pixel_estimate.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/walk_guide.h"

namespace volguide {

struct GuidedVolPathSettings {
    VolPathSettings walk;  // max_depth, rr_depth, hide_emitters, equiangular
    std::string training = "photons";
    int64_t photons = 1000000;  // the paper uses ~50 M; 1 M trains in seconds on two cores
    // Photon collisions kept at most (0: no cap): dense media deposit tens per photon, and the
    // field's build and fit time grows with them (4 M: 160 MB, ~3.5 s to build and fit on two
    // cores; on `aniso` 2 M photons deposit more than 8 M collisions, whose fit took 26 s uncapped).
    int64_t max_deposits = 4000000;
    // Focused photon emission (emission_focus.h): a pilot finds where each emitter lights a medium.
    bool photon_focus = true;
    int training_iterations = 5;  // progressive: iteration k traces 2^k spp (5: 31 spp in total)
    float training_fraction = 0.25f;
    GuidingFieldSettings field;  // leaf_samples -> field.tree.max_samples, lobes -> field.lobes
    std::string distance = "standard", direction = "phase", rrs = "standard";
    WalkGuideSettings guide;  // the guided decisions' parameters (c_T, p_max, filter_A, phase_prob)
    RouletteSplittingSettings roulette;  // rrs_window, rrs_q_min, rrs_q_max, rrs_max_branches
    std::string pixel_estimate = "raymarch";
    PixelEstimateSettings pixel;  // pixel_estimate_rays, pixel_estimate_floor
    int pixel_estimate_spp = 4;   // pixel_estimate=render
    std::string save_pixel_estimate;  // EXR of I (RGB, before the floor), empty = none
    std::string save_field, load_field;  // resolved paths, empty = none
    // `estimate`: none (render), or the field's own prediction of what the camera sees through the
    // media (cache_estimate.h): inscattered (compare with volpath volume_only) or incident.
    std::string estimate = "none";
    SourceLocation location;
    static GuidedVolPathSettings from(const Properties& props);
};

class GuidedVolPathIntegrator final : public Integrator {
public:
    explicit GuidedVolPathIntegrator(const Properties& props);
    // Guided RR/splitting compares with the pixel estimate at the camera ray's film position.
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    std::vector<std::pair<std::string, double>> statistics() const override;
    std::string to_string() const override;

    const GuidedVolPathSettings& settings() const { return settings_; }
    // The trained (or loaded) field; empty before preprocess().
    const GuidingField& field() const { return field_; }
    // The pixel estimate of guided RR/splitting; empty with rrs=standard.
    const PixelEstimate& pixel_estimate() const { return pixel_estimate_; }

private:
    GuidedVolPathSettings settings_;
    VolPathIntegrator walk_;
    GuidingField field_;
    std::unique_ptr<CacheEstimator> estimator_;  // estimate != none
    std::unique_ptr<WalkGuide> guide_;           // a guided distance, direction or RR decision
    std::unique_ptr<RouletteSplitting> rrs_;     // rrs != standard
    PixelEstimate pixel_estimate_;
    // The guided walk along ray, with guided RR/splitting (when rrs_) against the pixel value I.
    Color3 guided_walk(const Scene& scene, Sampler& sampler, const Ray& ray, float pixel) const;
    std::vector<std::pair<std::string, double>> training_stats_;  // of the last preprocess()
};

// The bounds the guiding field covers: the scene's shapes (media are bounded by shapes or grids).
BBox3f guiding_bounds(const Scene& scene);

}  // namespace volguide
