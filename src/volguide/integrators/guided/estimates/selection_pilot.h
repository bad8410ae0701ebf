#pragma once
// The pilot of learned selection (guiding/selection.h): a few camera samples per pixel of the
// guided walk with the configured mixtures and without guided RR/splitting, on their own random
// stream, recording per decision what guiding/selection.h needs. Not part of the image.
//
// SelectionRecorder (a PathRecorder of volpath's walk, path_recorder.h) follows one camera sample:
// every decision with its mixture densities at the sample and the contributions as they are added; at
// the end of the camera sample each decision's S (the sum of the contributions after it) is known and
// its terms go to the thread's SelectionStatistics. The pilot walks one branch per camera sample (no
// splitting), so S is a suffix sum.
#include <cstdint>
#include <functional>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/learned_selection.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class Scene;
struct PreprocessContext;

class SelectionRecorder final : public PathRecorder {
  public:
    // `cells`: the field's leaves + 1 (leaf -1 maps to the last, outside the field).
    SelectionRecorder(SelectionStatistics& stats, size_t cells) : stats_(stats), cells_(cells) {}

    // A new camera sample in a pixel of estimate `pixel` (> 0).
    void begin(float pixel);
    bool records_decisions() const override { return true; }
    // A decision in the cell of record.leaf sampled with density record.pdf from the mixture of
    // the unguided and guided densities p_u, p_g; one without a guided mixture only counts.
    void record_decision(DecisionKind kind, const DecisionRecord& record) override;
    void record_contribution(const Color3& c) override { total_ += double(c.average()); }
    // Adds the camera sample's terms to the statistics.
    void end();

  private:
    size_t cell(int leaf) const { return leaf >= 0 && size_t(leaf) + 1 < cells_ ? size_t(leaf) : cells_ - 1; }
    struct Pending {
        uint8_t kind = 0;  // SelectionDecision
        size_t cell = 0;
        float q = 0.f, p_u = 0.f, p_g = 0.f;
        double before = 0.0;  // contributions before it
    };
    SelectionStatistics& stats_;
    size_t cells_;
    float pixel_ = 1.f;
    double total_ = 0.0;
    uint64_t unrecorded_ = 0;
    std::vector<Pending> pending_;
};

// `spp` camera samples per pixel of `walk` (the guided walk with the recorder as its PathRecorder), each
// on Sampler(seed, pixel, k, stream of the pilot), `pixel(film_uv)` the pixel estimate; the sums of
// every recorder. Deterministic for any thread count (exact sums).
SelectionStatistics run_selection_pilot(const Scene& scene, int spp, size_t cells,
                                        const std::function<float(Point2f)>& pixel,
                                        const std::function<Color3(Sampler&, const Ray&, SelectionRecorder&)>& walk,
                                        const PreprocessContext& context);

}  // namespace volguide
