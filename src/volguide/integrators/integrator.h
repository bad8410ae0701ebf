#pragma once
// Integrators estimate the radiance arriving along a camera ray. The render loop
// (integrators/render_loop.h) drives them; they never touch the film or threads.
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/image.h"
#include "volguide/core/object.h"
#include "volguide/core/progress.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/core/vec.h"

namespace volguide {

class Scene;

// What a pre-pass needs from the render job: its seed (training must be reproducible), the time
// budget of the whole job, progress reporting and cancellation (Ctrl-C).
struct PreprocessContext {
    uint64_t seed = 0;
    double time_budget = 0;  // seconds for the whole render job; 0 = none
    // The render's samples per pixel (--spp, or the scene's sample_count without --time; 0: unknown, a
    // time budget decides): what a pre-pass without a time budget scales its probes with.
    int spp = 0;
    // Seconds the step given this context may take (0: no limit): a pre-pass step's share of the job's
    // budget (guided_volpath's PreprocessBudget), which the step's loops stop at.
    double time_limit = 0;
    ProgressCallback progress;
    const std::atomic<bool>* cancel = nullptr;
    // The pre-pass is saved and rendered by other processes (`volguide train`): what an integrator
    // would learn from its render's own passes it learns here instead, so that every process renders
    // with the same state (guided_volpath's allocation).
    bool learn_in_prepass = false;
    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

// A camera ray and the film position it leaves from, what an integrator estimates the radiance
// along (camera_sample.h makes them). Integrators that keep per-pixel data (guided_volpath's pixel
// estimate) read the position; the others only the ray.
struct CameraRay {
    Ray ray;
    Point2f film_uv;  // [0, 1]^2 over the film; outside it in a filter's border
};

// Where a light tracer's paths land on the film (film position in pixels, value). The render loop
// gives each light path its own and sums them in a fixed order (integrators/light_tracing.h).
class FilmSplats {
public:
    virtual void splat(Point2f film_pos, const Color3& value) = 0;

protected:
    ~FilmSplats() = default;
};

// What the render loop says of a pass once it is merged into the image (Integrator::end_pass).
struct PassReport {
    int spp_done = 0;         // samples per pixel in the image so far
    int spp = 0;              // of this pass
    double seconds = 0;       // since the job started (preprocessing included), like the time budget
    double pass_seconds = 0;  // this pass's rendering alone
    // The pass's per-sample noise: the mean over the film's pixels of the unbiased variance of the
    // pass's samples' luminance divided by (m^2 + 0.01), m the pixel's luminance in the image when the
    // first pass of two or more samples per pixel was merged (one normaliser for the whole render),
    // the benchmark's relMSE per sample with its epsilon (docs/theory.md §22.4). NaN for passes of one
    // sample per pixel, for that first pass of two or more, and for light tracers (a light path lands
    // on many pixels). A pure function of the samples: the same for any thread count.
    double relative_variance = std::numeric_limits<double>::quiet_NaN();
    // Its standard error over the pixels (NaN with it).
    double relative_variance_error = std::numeric_limits<double>::quiet_NaN();
};

class Integrator : public Object {
public:
    // Radiance along a camera ray, one sample.
    virtual Color3 Li(const Scene& scene, Sampler& sampler, const CameraRay& camera) const = 0;
    // Light tracers (ptracer) do not estimate along camera rays: they trace one path from the emitters
    // per call and splat its connections to the sensor; the image is the splats' sum over the film
    // divided by the samples per pixel. The render loop calls trace_from_emitters instead of Li then.
    virtual bool traces_from_emitters() const { return false; }
    virtual void trace_from_emitters(const Scene& scene, Sampler& sampler, FilmSplats& splats) const {}
    // The `moment` integrator also writes the per-sample variance image.
    virtual bool writes_variance() const { return false; }
    // Work before rendering (training, pre-passes), counted in the time budget. Default: none.
    virtual void preprocess(const Scene& scene, const PreprocessContext& context) {}
    // After each render pass is merged into the image (PassReport: samples per pixel so far, the
    // job's seconds, the pass's noise). Integrators that learn from their own render's samples
    // (openpgl_volpath, as Cycles trains Open PGL) or refine their guide (guided_volpath) update
    // there, between passes, so that every pass samples one fixed distribution. Default: nothing.
    virtual void end_pass(const PassReport& pass) {}
    // Named counters of the last render (e.g. guided decisions), for --stats. Default: none.
    virtual std::vector<std::pair<std::string, double>> statistics() const { return {}; }

    // The pre-pass as data (`volguide train` / `render --field`, docs/distributed.md). An integrator
    // whose preprocess() computes something worth sharing (guided_volpath: the guiding field and
    // the pixel estimate) returns true from has_prepass_state(); prepass_state() is then the bytes
    // of what the last preprocess() computed, and after use_prepass_state(bytes) the next
    // preprocess() takes them instead of training (throws std::runtime_error for bytes it cannot
    // read). The bytes are deterministic: equal bytes, equal renders.
    virtual bool has_prepass_state() const { return false; }
    virtual std::string prepass_state() const;
    virtual void use_prepass_state(const std::string& bytes);

    // What the render's passes changed in the integrator since preprocess() (a render checkpoint,
    // integrators/render_state.h): after preprocess() of the same scene, options and seed,
    // restore_render_state(render_state()) makes the next pass sample exactly what it would have in the
    // checkpointed render. Default: nothing (an integrator that does not learn between passes);
    // restore_render_state then accepts only empty bytes. Throws std::runtime_error for bytes it cannot
    // read. An integrator whose state cannot be captured says why in render_state_unsupported()
    // ("" when it can): a checkpointed render refuses it before rendering.
    virtual std::string render_state() const { return {}; }
    virtual void restore_render_state(const std::string& bytes);
    virtual std::string render_state_unsupported() const { return {}; }

    // The integrator's plugin type and parameters, canonical (integrator_configuration.h), set by
    // the factory: what a trained pre-pass and the parts of a distributed render are checked against.
    const std::string& configuration() const { return configuration_; }
    void set_configuration(std::string configuration) { configuration_ = std::move(configuration); }

private:
    std::string configuration_;
};

}  // namespace volguide
