#pragma once
// A deliberately naive volumetric path tracer, the reference volpath is tested against: free-flight
// sampling (Medium::sample_free_flight), phase and BSDF sampling only, no next-event estimation;
// light is collected only when a path hits an emitter (or leaves the scene). Same depth semantics as
// volpath (null crossings do not count), so both render the same image with different noise.
// XML type `simple_volpath` (a volguide extension; parameters max_depth, rr_depth, hide_emitters).
#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class SimpleVolPathIntegrator final : public Integrator {
public:
    explicit SimpleVolPathIntegrator(const Properties& props);
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    std::string to_string() const override;

private:
    int max_depth_ = -1, rr_depth_ = 5;
    bool hide_emitters_ = false;
};

}  // namespace volguide
