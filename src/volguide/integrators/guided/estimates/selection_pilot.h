#pragma once
// The pilot of learned selection (guiding/selection.h): a few camera samples per pixel of the
// guided walk with the configured mixtures and without guided RR/splitting, on their own random
// stream, recording per decision what guiding/selection.h needs. Not part of the image.
//
// SelectionRecorder (a PathRecorder of volpath's walk, path_recorder.h) follows one camera sample:
// every decision with its mixture densities at the sample, every continuation point with the
// field's estimate there and the path weight, and the contributions as they are added; at the end of the camera sample each decision's S (the sum of
// the contributions after it) is known and its terms go to the thread's SelectionStatistics. The
// pilot walks one branch per camera sample (no splitting), so S is a suffix sum.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/guiding/selection.h"
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
    // The round of the per-cell method choice this recorder serves (selection.h; -1: none): its
    // distance decisions are recorded per method, mixture or not, and its vertices' counted work
    // (guided decisions, continuation points) per cell for the cost model.
    void set_method_round(int method) { method_ = method; }
    // The cost model the round counts with, and (not null: the render's guided RR/splitting, which
    // the pilot walks without) the roulette whose splitting factor is charged at the round's
    // continuation points: q - 1 times the counted cost of what followed the point (docs/theory.md §7.12).
    void set_costs(const SelectionCosts& costs, const RouletteSplittingSettings* splitting) {
        costs_ = costs;
        splitting_ = splitting;
    }
    bool records_decisions() const override { return true; }
    // A decision in the cell of record.leaf sampled with density record.pdf from the mixture of
    // the unguided and guided densities p_u, p_g; one without a guided mixture only counts (the
    // cost model counts it).
    void record_decision(DecisionKind kind, const DecisionRecord& record) override;
    // A continuation point of `stage` in the cell of `vertex_leaf.leaf`: the field's estimate of what
    // the path collects from here on per unit weight, and the path weight (channel averages).
    void record_continuation(ContinuationStage stage, const VertexLeaf& vertex_leaf, const Vec3f& w,
                             float estimate, const Color3& throughput) override;
    void record_contribution(const Color3& c) override { total_ += double(c.average()); }
    // Adds the camera sample's terms to the statistics.
    void end();

  private:
    void count_cost(DecisionKind kind, const DecisionRecord& record);
    double split_scale() const;
    size_t cell(int leaf) const { return leaf >= 0 && size_t(leaf) + 1 < cells_ ? size_t(leaf) : cells_ - 1; }
    struct Pending {
        bool is_decision = true;
        bool is_method = false;  // a distance decision of a method round
        uint32_t lookups = 0;
        uint8_t kind = 0;  // SelectionDecision or stage
        size_t cell = 0;
        float q = 0.f, p_u = 0.f, p_g = 0.f;  // decision
        float estimate = 0.f, beta = 0.f;     // continuation
        float split = 0.f;                    // continuation: the render's q - 1
        double before = 0.0;                  // contributions before it
        double cost_before = 0.0;             // counted cost (ns) before it
    };
    SelectionStatistics& stats_;
    size_t cells_;
    float pixel_ = 1.f;
    double total_ = 0.0;
    uint64_t unrecorded_ = 0;
    std::array<uint64_t, kSelectionDecisions> decisions_{};  // of the camera sample per kind, recorded or not
    int method_ = -1;
    SelectionCosts costs_;
    const RouletteSplittingSettings* splitting_ = nullptr;
    double cost_ = 0.0;  // counted cost (ns) of the camera sample so far (method rounds)
    std::vector<Pending> pending_;
};

// `spp` camera samples per pixel of `walk` (the guided walk with the recorder as its PathRecorder), each
// on Sampler(seed, pixel, k, stream of the pilot), `pixel(film_uv)` the pixel estimate; the sums of
// every recorder. Deterministic for any thread count (exact sums). `method_round` >= 0: the round of
// that DistanceMethod (the walk's guide forces it in every cell; the rounds share their random numbers),
// counted with `costs` and charged `splitting`'s copies (SelectionRecorder::set_costs).
SelectionStatistics run_selection_pilot(
    const Scene& scene, int spp, size_t cells, const std::function<float(Point2f)>& pixel,
    const std::function<Color3(Sampler&, const Ray&, SelectionRecorder&)>& walk, const PreprocessContext& context,
    int method_round = -1, const SelectionCosts& costs = {}, const RouletteSplittingSettings* splitting = nullptr);

}  // namespace volguide
