#pragma once
// The paper's training pre-pass (docs/theory.md §5.2, §10.1): photons leave the lights (an emitter
// chosen in proportion to its power, position and direction by its emission sampling), travel by
// the media's free-flight sampling and BSDF sampling (importance transport), and at every real
// collision inside a medium deposit a radiance sample for the guiding field:
//   position, the arriving direction -omega_travel (towards the light), and the flux arriving at
//   the collision divided by sigma_t (collision estimator, before the albedo).
// Photon i draws its random numbers from Sampler(seed, kPhotonStream, i), and batches are joined in
// photon order, so the samples are a pure function of (scene, settings, seed) for any thread count;
// so is the focus, from the pilot's own stream.
#include <cstdint>
#include <vector>

#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class Scene;

struct PhotonPassSettings {
    int64_t photons = 1000000;
    // Photon i of this pass draws from the photon stream's index first_photon + i: a later pass of
    // one render (guided_volpath's refinement) traces new photons, never the earlier passes' again.
    int64_t first_photon = 0;
    int max_depth = -1;  // scattering events per photon (-1: until Russian roulette ends it)
    int rr_depth = 5;
    double time_limit = 0;  // seconds (> 0): stop starting new photon batches after this long
    // Stop once this many collisions were deposited (0: no cap). In dense media every photon deposits
    // tens of collisions, and the field's build and fit cost grows with the deposits, not the
    // photons: the cap keeps training inside its budget. Checked after each wave of kWaveBatches
    // batches, so the result does not depend on the thread count.
    int64_t max_deposits = 0;
    // Focused emission (integrators/guided/training/emission_focus.h): a pilot of pilot_photons (0: photons / 8,
    // at most 2^20) finds the parts of each emitter that light a medium; emission then picks them
    // with probability 1 - focus_defensive (the photons' flux compensates: unbiased).
    bool focus = true;
    int64_t pilot_photons = 0;
    float focus_defensive = 0.02f;
};

struct PhotonPassResult {
    std::vector<RadianceSample> samples;
    int64_t photons_traced = 0;  // fewer than requested when cancelled
    int64_t collisions = 0;
    bool deposit_limited = false;  // stopped by max_deposits
    int64_t pilot_photons = 0;         // traced to focus the emission (not deposited)
    int64_t photons_depositing = 0;    // photons (of photons_traced) that deposited at least once
};

PhotonPassResult trace_photons(const Scene& scene, const PhotonPassSettings& settings, const PreprocessContext& context);

}  // namespace volguide
