#pragma once
// guided_volpath's training in two stages (issue 59): training that stops when it cannot pay. The
// pre-pass traces a fraction of the photons (kCoarseDivisor) into a coarse field; the render's first
// passes learn the allocation on it (estimates/allocation.h); after kDecideSpp samples per pixel the
// allocation's predicted gain decides: below kPaysGain nothing guided can pay for more training, and the
// render goes on as the unguided walk
// (bounded volpath's, its early passes kept: every pass is unbiased); otherwise the rest of the photons
// are traced, the full field is built from all of them and the allocation is learned again on it; when
// kConfirmSpp samples per pixel later the gain on the full field, measured against control samples of
// the unguided walk, is below kPaysGain, the render goes on
// unguided as well (nothing recorded). What the stages keep between passes is this record.
#include <cstdint>
#include <vector>

#include "volguide/guiding/guiding_field.h"

namespace volguide {

enum class TrainingStage {
    Coarse,   // the coarse field: the allocation's first passes decide
    Full,     // the full field (or a given or loaded one): nothing more to decide
    Stopped,  // nothing paid: the unguided walk renders the rest
};

struct StagedTraining {
    static constexpr int64_t kCoarseDivisor = 4;
    static constexpr int kDecideSpp = 4;
    static constexpr double kPaysGain = 1.05;
    static constexpr int kConfirmSpp = 16;

    TrainingStage stage = TrainingStage::Full;
    std::vector<RadianceSample> deposits;  // the coarse stage's, weighted for its photons alone
    int64_t photons_traced = 0;            // by the coarse stage
    int64_t photon_stream_next = 0;        // the first photon index the full stage draws from
    double seconds = 0;                    // the training's seconds so far (photons, fit, pixel estimate)
    int full_from = 0;                     // the samples per pixel when the full stage began
};

}  // namespace volguide
