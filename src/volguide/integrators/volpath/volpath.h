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
//    power heuristic (see equiangular_mis.h). Heterogeneous media keep distance sampling (warning).
//  - `volume_only` (default false, a volguide extension): only light whose camera path scatters
//    first in a medium — the "V" image of docs/theory.md §12.2, which is the integral of T sigma_s L_i
//    along the camera ray (the reference of the guiding field's in-scattered estimate).
//  - `forward_first_scatter` (default false, an inspection extension): the camera path's first
//    medium scattering keeps its direction (a forward delta phase function, weight 1, no NEE there).
//    With volume_only the image is the integral of T sigma_s L(x, d), the radiance from straight
//    ahead — the reference of the field's incident estimate.
//  - `rr_rule` (default "mitsuba", a volguide extension): the Russian roulette played once per
//    depth from rr_depth on. "mitsuba" is Mitsuba 3's rule, survival q = min(max(beta) eta^2, 0.95):
//    the same noise as Mitsuba, but once max(beta) > 0.95 every event multiplies the weight by
//    albedo / 0.95, unbounded (infinite variance) for albedo > 0.95 in deep media. "bounded" survives
//    with q = min(1, max(beta) eta^2) (pbrt-v4's rule): a weight below 1 is brought back to 1 and
//    never above it, so a path's weight stays bounded in high-albedo media.
#include <tbb/enumerable_thread_specific.h>

#include "volguide/core/properties.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/volpath/work.h"

namespace volguide {

class PathRecorder;
class WalkPolicy;

// The Russian roulette rule (see `rr_rule` above).
enum class RouletteRule { Mitsuba, Bounded };

// The survival probability of the throughput Russian roulette for `beta_max_eta2` = max(beta) eta^2.
float roulette_survival(RouletteRule rule, float beta_max_eta2);
const char* roulette_rule_name(RouletteRule rule);

struct VolPathSettings {
    int max_depth = -1;
    int rr_depth = 5;
    bool hide_emitters = false;
    bool equiangular = false;
    bool volume_only = false;
    bool forward_first_scatter = false;
    RouletteRule rr_rule = RouletteRule::Mitsuba;
    static VolPathSettings from(const Properties& props);
};

// Counted work as --stats names ("work_" + kWorkNames).
std::vector<std::pair<std::string, double>> named_work(const WorkCounts& work);

class VolPathIntegrator final : public Integrator {
public:
    explicit VolPathIntegrator(const Properties& props) : settings_(VolPathSettings::from(props)) {}
    explicit VolPathIntegrator(VolPathSettings s) : settings_(s) {}
    Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const override;
    // The walk of one camera ray (volpath_walk.h) with `policy` (null: the unguided walk) making the
    // decisions guiding or guided RR/splitting change (walk_policy.h), and `recorder` (null: none)
    // recording the path (path_recorder.h). Equiangular sampling is not combined with a policy
    // that guides distances; training recorders need equiangular = false (the recorder's NEE
    // samples assume NEE and phase sampling are the only direct-light strategies).
    // `work` (null: not wanted): the walk's counted work (work.h) is added to it.
    Color3 walk(const Scene& scene, Sampler& sampler, const Ray& ray, WalkPolicy* policy,
                PathRecorder* recorder = nullptr, WorkCounts* work = nullptr) const;
    void preprocess(const Scene& scene, const PreprocessContext& context) override;
    // The render's counted work (work.h) as "work_<unit>" totals (what bench/fit_cost_model.py fits).
    std::vector<std::pair<std::string, double>> statistics() const override { return named_work(total_work()); }
    // The counted work of the camera samples Li rendered since the last preprocess().
    WorkCounts total_work() const;
    std::string to_string() const override;
    const VolPathSettings& settings() const { return settings_; }

private:
    VolPathSettings settings_;
    mutable tbb::enumerable_thread_specific<WorkCounts> work_;
};


}  // namespace volguide
