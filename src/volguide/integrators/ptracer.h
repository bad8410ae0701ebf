#pragma once
// Mitsuba 3's `ptracer`: a particle (light) tracer. Each sample traces one path from an emitter
// (chosen by power, as photon emission), BSDF-sampled in importance mode, and at every surface vertex
// connects to the sensor and splats there; with hide_emitters false each sample also connects one
// point seen on a non-delta emitter to the sensor (the directly visible emitters). Its expected image is
// `path`'s (docs/scene-format.md). Semantics of max_depth (path segments, the sensor connection
// included), rr_depth (roulette from that depth, q = min(max throughput · eta², 0.95)) and the
// shading-normal correction of the adjoint BSDF (Veach's thesis, p. 155) as Mitsuba's. Surfaces only
// (no media), pinhole sensors only.
#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class BSDF;
struct SurfaceInteraction;

struct PtracerSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool hide_emitters = false;
    // Mitsuba's samples_per_pass groups its work; volguide's passes are the render loop's, so it only
    // has to be valid (> 0, or -1 = all): the image does not depend on it.
    int samples_per_pass = -1;
    static PtracerSettings from(const Properties& props);
};

class ParticleTracerIntegrator final : public Integrator {
  public:
    explicit ParticleTracerIntegrator(const Properties& props) : settings_(PtracerSettings::from(props)) {}
    explicit ParticleTracerIntegrator(PtracerSettings s) : settings_(s) {}
    // Not an estimator along camera rays: throws std::logic_error (the render loop calls
    // trace_from_emitters).
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    bool traces_from_emitters() const override { return true; }
    void trace_from_emitters(const Scene& scene, Sampler& sampler, FilmSplats& splats) const override;
    std::string to_string() const override;

  private:
    void splat_visible_emitter(const Scene& scene, Sampler& sampler, FilmSplats& splats) const;
    void trace_light_path(const Scene& scene, Ray ray, Color3 throughput, Sampler& sampler,
                          FilmSplats& splats) const;
    void connect_surface(const Scene& scene, const SurfaceInteraction& si, const BSDF& bsdf,
                         const Color3& throughput, FilmSplats& splats) const;

    PtracerSettings settings_;
};

}  // namespace volguide
