#pragma once
// Volumetric path tracer with Mitsuba 3's `volpath` semantics (`volpathmis` maps here too: it
// renders the same image).
//  - The ray's medium starts as the sensor's and changes at every surface crossing of a shape with
//    interior/exterior media (Shape::target_medium with the geometric normal).
//  - Free-flight sampling inside media up to the next surface; at medium scattering vertices NEE
//    (when the medium samples emitters) and phase sampling, combined by MIS (power heuristic); at
//    surfaces emission, NEE and BSDF sampling with MIS as `path`.
//  - max_depth counts real scattering events only: crossing a null surface (null BSDF, the Null
//    lobe of thindielectric) keeps the depth; max_depth = 1 shows only directly visible emitters.
//  - NEE shadow rays pass through null surfaces and multiply every medium segment's transmittance
//    and eval_null_transmission(). The MIS weight of a BSDF/phase-sampled emitter hit uses the pdf
//    of the last real scattering vertex and the emitter pdf seen from it, exactly the pair NEE used.
//  - `equiangular` (default false): in homogeneous media, equiangular sampling towards point, spot
//    and area lights, combined with distance sampling + NEE and with phase sampling by a three-way
//    power heuristic (see volpath.cpp). Heterogeneous media keep distance sampling (warning).
//  - `volume_only` (default false, a volguide extension): only light whose camera path scatters
//    first in a medium — the "V" image of theory.md §12.2, which is the integral of T sigma_s L_i
//    along the camera ray (the reference of the guiding field's in-scattered estimate).
//  - `forward_first_scatter` (default false, an inspection extension): the camera path's first
//    medium scattering keeps its direction (a forward delta phase function, weight 1, no NEE there).
//    With volume_only the image is the integral of T sigma_s L(x, d), the radiance from straight
//    ahead — the reference of the field's incident estimate.
#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class TrainingRecorder;
class WalkGuide;
class RouletteSplitting;

// Guided Russian roulette and splitting of one camera sample (roulette_splitting.h): the decision
// rule and the estimate I of the pixel the sample lands in.
struct WalkSplitting {
    const RouletteSplitting* rrs = nullptr;
    float pixel = 0.f;
};

struct VolPathSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool hide_emitters = false;
    bool equiangular = false;
    bool volume_only = false;
    bool forward_first_scatter = false;
    static VolPathSettings from(const Properties& props);
};

class VolPathIntegrator final : public Integrator {
public:
    explicit VolPathIntegrator(const Properties& props) : settings_(VolPathSettings::from(props)) {}
    explicit VolPathIntegrator(VolPathSettings s) : settings_(s) {}
    Color3 Li(const Scene& scene, Sampler& sampler, const Ray& ray) const override;
    // The same walk, reporting its medium vertices and contributions to `recorder` (may be null)
    // for progressive training (training_recorder.h). Training uses equiangular = false: the
    // recorder's NEE samples assume NEE and phase sampling are the only direct-light strategies.
    Color3 Li(const Scene& scene, Sampler& sampler, const Ray& ray, TrainingRecorder* recorder) const;
    // The same walk with `guide` (may be null) making the distance and direction decisions in media
    // (guided_volpath, walk_guide.h). Equiangular sampling is not combined with a distance guide.
    // With `splitting` (and a guide, whose field estimates E[X]), guided RR and splitting after
    // the distance and direction decisions at medium vertices (theory.md §9.3): split copies wait
    // on a per-thread stack and draw from streams forked off the sample's; surfaces keep
    // throughput RR, which a medium vertex's guided decision replaces at its depth.
    Color3 Li(const Scene& scene, Sampler& sampler, const Ray& ray, TrainingRecorder* recorder,
              const WalkGuide* guide, const WalkSplitting* splitting = nullptr) const;
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    std::string to_string() const override;
    const VolPathSettings& settings() const { return settings_; }

private:
    VolPathSettings settings_;
};

}  // namespace volguide
