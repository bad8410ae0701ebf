#pragma once
// Mitsuba 3's `direct` integrator: direct illumination only. At the first surface the camera ray
// hits, `emitter_samples` emitter samples and `bsdf_samples` BSDF samples, combined by the power
// heuristic on the sample-count-weighted pdfs (one-sample-per-strategy MIS with n_e and n_b samples:
// each strategy's pdf times its share of the samples); plus the emitter the camera sees, unless
// hide_emitters. Both counts default to `shading_samples` (default 1).
#include "volguide/core/properties.h"
#include "volguide/geometry/interaction.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

struct DirectSettings {
    int emitter_samples = 1;
    int bsdf_samples = 1;
    bool hide_emitters = false;
    static DirectSettings from(const Properties& props);
};

class DirectIntegrator final : public Integrator {
  public:
    explicit DirectIntegrator(const Properties& props) : settings_(DirectSettings::from(props)) {}
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    std::string to_string() const override;

  private:
    Color3 emitter_sampling(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si) const;
    Color3 bsdf_sampling(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si) const;
    // The share of all samples each strategy takes (MIS weights compare pdf × share).
    float emitter_share() const;
    float bsdf_share() const { return 1.f - emitter_share(); }
    DirectSettings settings_;
};

}  // namespace volguide
