#pragma once
// Mitsuba's `moment` integrator: renders with one nested integrator and also reports the
// per-sample variance (the render loop accumulates the second moment; the CLI writes
// <output stem>_var.exr).
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class MomentIntegrator final : public Integrator {
public:
    explicit MomentIntegrator(const Properties& props);
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override {
        return nested_->Li(scene, sampler, camera);
    }
    bool writes_variance() const override { return true; }
    void preprocess(const Scene& scene, const PreprocessContext& context) override {
        nested_->preprocess(scene, context);
    }
    // The nested integrator's pre-pass (volguide train / render --field).
    bool has_prepass_state() const override { return nested_->has_prepass_state(); }
    std::string prepass_state() const override { return nested_->prepass_state(); }
    void use_prepass_state(const std::string& bytes) override { nested_->use_prepass_state(bytes); }
    const Integrator& nested() const { return *nested_; }
    void end_pass(const PassReport& pass) override { nested_->end_pass(pass); }
    // The nested integrator's render state (checkpoints).
    std::string render_state() const override { return nested_->render_state(); }
    void restore_render_state(const std::string& bytes) override { nested_->restore_render_state(bytes); }
    std::string render_state_unsupported() const override { return nested_->render_state_unsupported(); }
    std::vector<std::pair<std::string, double>> statistics() const override { return nested_->statistics(); }
    std::string to_string() const override { return "moment[" + nested_->to_string() + "]"; }

private:
    std::shared_ptr<Integrator> nested_;
};

}  // namespace volguide
