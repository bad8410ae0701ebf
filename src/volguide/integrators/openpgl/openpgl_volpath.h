#pragma once
// `openpgl_volpath`: Intel Open PGL's directional path guiding driven the way Blender Cycles
// drives it, as a peer to compare volguide's guiding with (issue 19). The render is volpath's walk
// with an OpenPglWalkPolicy (openpgl_walk_policy.h): guided directions at medium vertices and at
// diffuse surfaces, free-flight distances, throughput RR.
//
// Training is online, from the render's own camera paths: while training, every camera path is
// recorded as Open PGL path segments (openpgl_path_recorder.h), and after each render pass
// (render_loop.h: 1, 1, 2, 4, 8, 8, ... spp) the field is updated with that pass's samples
// (Integrator::end_pass), until training_spp samples per pixel or, under --time, the first pass past
// training_fraction of the budget. Each pass samples one fixed field, and every pass, training or
// not, counts toward the image (as in Cycles): the estimator is unbiased for any field.
#include <memory>

#include <tbb/enumerable_thread_specific.h>

#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/openpgl/openpgl_field.h"
#include "volguide/integrators/openpgl/openpgl_settings.h"
#include "volguide/integrators/openpgl/openpgl_walk_policy.h"

namespace volguide {

class OpenPglVolPathIntegrator final : public Integrator {
  public:
    explicit OpenPglVolPathIntegrator(const Properties& props);
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    // A fresh field over the scene's bounds (every render trains its own).
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    // While training: Field::Update with the pass's samples.
    void end_pass(const PassReport& pass) override;
    // Its field lives inside Open PGL, which has no way to save its sample storage and training state.
    std::string render_state_unsupported() const override {
        return "openpgl_volpath's Open PGL field and sample storage cannot be saved";
    }
    std::vector<std::pair<std::string, double>> statistics() const override;
    std::string to_string() const override;
    const OpenPglSettings& settings() const { return settings_; }

  private:
    OpenPglThreadState& thread_state() const;

    OpenPglSettings settings_;
    VolPathIntegrator walk_;
    std::unique_ptr<OpenPglField> field_;
    double time_budget_ = 0;
    bool training_ = false;
    int training_spp_done_ = 0;
    double training_seconds_ = 0;   // job time at the end of the last training update
    double update_seconds_ = 0;     // spent in Field::Update
    // One per worker thread, made on its first camera sample (Open PGL's distributions are
    // per-thread objects); cleared with the field in preprocess().
    mutable tbb::enumerable_thread_specific<std::unique_ptr<OpenPglThreadState>> threads_;
};

}  // namespace volguide
