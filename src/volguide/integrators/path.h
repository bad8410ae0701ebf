#pragma once
// Unidirectional path tracer with next-event estimation and MIS (power heuristic), with
// Mitsuba 3's `path` semantics: max_depth counts path segments (1 = only directly visible
// emitters, 2 = direct illumination, -1 = unbounded), rr_depth is the depth from which Russian
// roulette is used, hide_emitters hides directly visible emitters.
#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

struct PathSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool hide_emitters = false;
    static PathSettings from(const Properties& props);
};

class PathIntegrator final : public Integrator {
public:
    explicit PathIntegrator(const Properties& props) : settings_(PathSettings::from(props)) {}
    explicit PathIntegrator(PathSettings s) : settings_(s) {}
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    std::string to_string() const override;

private:
    PathSettings settings_;
};

}  // namespace volguide
