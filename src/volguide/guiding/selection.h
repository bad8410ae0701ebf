#pragma once
// Learned selection (issue 21): per cell of the guiding field (its kd leaves, plus one cell for
// everything outside the field), how much each guided decision is trusted — the guided share of the
// distance decision's mixture (1 - c_T), of the medium direction mixture (1 - phase_prob) and of
// the diffuse surface mixture (1 - bsdf_prob) — and whether guided RR/splitting acts there. Learned
// from a pilot: a few camera samples per pixel with the configured mixtures, after training.
//
// The mixtures: every decision is a one-sample mixture q_a = (1 - a) p_u + a p_g of the unguided
// (p_u: free flight, phase function, BSDF) and the guided density p_g, with guided share a. For one
// decision sampled from q_cur, with S the contribution of everything after it to the camera sample
// and I the pixel estimate, the pixel's second moment attributable to it under share a is
//   M(a) = E_cur[(S / I)^2 q_cur / q_a]
// (the path's prefix weight cancels: S = beta f R / q_cur). SelectionStatistics sums these terms
// per cell and decision for every share of kSelectionShares at once (one sample serves all).
// fit() then picks per cell the share that minimises the render's variance x time:
//   argmin_a  M_r(a) / V + n_r kappa [a > 0] / T,
// V the pixel estimator's second moment (the pilot's sum of (X / I)^2 over camera samples, X the
// camera sample's value; a decision's choice changes the second moment of what follows it by
// M_r(a) - M_r(pilot's), and nothing before it; these changes do not add up over the decisions of
// one path, each of whose M counts everything after it, so V stays the pilot's), T the
// cost in decisions (each decision 1, a guided one 1 + kappa of its kind, SelectionSettings): the
// marginal rule of minimising V x T over independent cells, iterated three times. A cell that loses with guiding gets share 0:
// the walk then makes volpath's decision there and pays nothing for guiding (no walk over bins, no
// product built).
//
// With rrs_ratio > 0 (off by default), guided RR/splitting acts in a cell only where the field's
// estimate E of what a vertex collects agrees with what the pilot's paths collected there,
// (sum S / beta) / (sum E) within [1 / rrs_ratio, rrs_ratio]: meant for leaves estimated too dark
// (they kill the paths that carry their light) or too bright (splitting for nothing); measured, it
// does more harm than good (SelectionSettings::rrs_ratio).
//
// Per-cell method (issue 37, docs/theory.md §7.12; SelectionSettings::choose_distance_method): the
// pilot runs once per method of DistanceMethod, every cell forced to it, and records per cell and
// method the sum of (S / I)^2 over its distance decisions and the counted work of the cell's vertices
// in that round (CostEvent: decisions, lookups, guided directions, estimate reads — counts, never
// time: the same for any thread count). fit() picks per cell
//   argmin_m  M_r(m) / V + C_r(m) / T,   C_r(m) = sum over the cell's events of cost_ns[event],
// V the pilot's camera-sample second moment and T its total cost (the cells' chosen methods plus
// what no cell holds), shrunk towards the pooled mean as the shares are. Free flight costs no
// lookup: a cell that chooses it makes volpath's distance decision and reads nothing of the field for
// it; the other decisions of its vertices stay guided. Volpath: every decision of a vertex in the
// cell is volpath's (free flight, the phase function, the BSDF, the walk's throughput roulette),
// nothing of the field is read for them beyond finding the cell.
// Only probabilities change: any learned value gives an unbiased estimator. Sums are exact
// (fixed point, 128-bit integers), so the result is independent of the order the pilot's samples
// arrive in, hence of the thread count. Cells with fewer than min_samples pilot decisions keep the
// configured mixture (kDefault).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace volguide {

enum class SelectionDecision : uint8_t { Distance = 0, Direction = 1, Surface = 2 };
inline constexpr int kSelectionDecisions = 3;
// Continuation stages of guided RR/splitting (walk_policy.h's ContinuationStage order).
inline constexpr int kSelectionStages = 2;
// The guided shares the pilot evaluates.
inline constexpr std::array<float, 6> kSelectionShares = {0.f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f};
// The methods a cell can choose among: the distance decision of the integrators' distance=standard,
// vsp, vsp_product, incremental (the other decisions guided as configured), and volpath (every
// decision of the cell's vertices unguided, no guided RR/splitting); kMethodDefault: keep the configured one.
enum class DistanceMethod : uint8_t { FreeFlight = 0, Vsp = 1, VspProduct = 2, Bins = 3, Volpath = 4 };
inline constexpr int kDistanceMethods = 5;
inline constexpr uint8_t kMethodDefault = 255;
inline constexpr std::array<const char*, kDistanceMethods> kDistanceMethodNames = {"free_flight", "vsp", "vsp_product",
                                                                                  "bins", "volpath"};

// The counted work of the method choice's cost model (docs/theory.md §7.12): per cell and round, how
// many of each event its vertices made.
enum class CostEvent : uint8_t {
    Segment = 0,          // a distance decision's segment: its intersection, the vertex's NEE ray, the unguided sampling
    DistanceDecision = 1, // the distance decision itself (its cost depends on the round's method)
    BinLookup = 2,        // one field lookup of the incremental bins
    GuidedDirection = 3,  // a guided direction decision: the product built, the mixture sampled, its pdf for NEE's MIS
    GuidedSurface = 4,    // a guided surface decision: the cosine product, the mixture sampled
    Continuation = 5,     // a continuation point: guided RR/splitting reads the field's estimate there
};
inline constexpr int kCostEvents = 6;

// Cost constants in ns per event (bench/RESULTS.md "issue 37: the cost model" says where each comes
// from); the time of a cell's round is estimated from counts, never measured, so the choice is the
// same for any thread count.
struct SelectionCosts {
    float segment = 460.f;
    std::array<float, kDistanceMethods> decision = {68.f, 128.f, 306.f, 68.f, 68.f};  // per DistanceMethod
    float bin_lookup = 120.f;
    float guided_direction = 674.f;
    float guided_surface = 674.f;
    float estimate = 53.f;
};

struct SelectionSettings {
    int pilot_spp = 2;  // camera samples per pixel of the pilot (0: no learned selection)
    int min_samples = 32;  // pilot decisions a cell needs before its choice is learned
    // Weight, in pilot decisions, of the mean pooled over all cells in each cell's mean second
    // moment per decision (shrinkage of noisy per-cell estimates, fit()).
    float prior_samples = 256.f;
    // Extra cost of a guided decision, in units of an unguided one (distance, direction, surface):
    // guided distance decisions switched off almost everywhere in thin fog saved a quarter of the
    // render time at equal spp, which these units reproduce (bench/RESULTS.md (issue 35)). Without the
    // shrinkage of fit() a short pilot's per-cell moments are too noisy to weigh against a cost.
    std::array<float, kSelectionDecisions> kappa = {1.f, 0.25f, 0.25f};
    // Guided RR/splitting acts where measured / estimated is within [1/r, r]; 0: always (the
    // default: with r = 3 the gate switched it off in many of aniso's leaves and relMSE rose at
    // equal spp, bench/RESULTS.md (issue 35): a leaf's estimate can be off by a factor and still split
    // well).
    float rrs_ratio = 0.f;
    // Choose the distance method per cell (above); off by default (its pilot costs one round per method).
    bool choose_distance_method = false;
    // The cost model of the per-cell method choice (ns per counted event).
    SelectionCosts costs;
};

// An exact sum of non-negative terms: fixed point with 2^-32 resolution in 128 bits (two words),
// each term clamped to 1e15.
class ExactSum {
  public:
    void add(double term);
    ExactSum& operator+=(const ExactSum& o);
    double value() const;

  private:
    void add_words(uint64_t hi, uint64_t lo);
    uint64_t hi_ = 0, lo_ = 0;
};

class SelectionStatistics {
  public:
    SelectionStatistics() = default;
    // `cells`: the field's leaves + 1 (the last: outside the field).
    explicit SelectionStatistics(size_t cells);
    size_t cells() const { return moments_.size(); }

    // One decision in `cell` sampled with density q_cur, whose unguided and guided densities at
    // the sample are p_u and p_g; s2 = (S / I)^2 of what followed it.
    void add_decision(SelectionDecision d, size_t cell, double s2, float q_cur, float p_u, float p_g);
    // One continuation point: the field's estimate there and the radiance measured after it (S / beta).
    void add_continuation(int stage, size_t cell, double estimate, double measured);
    // Every decision of the pilot's walks, recorded or not (the cost model's unit).
    void add_unrecorded_decisions(uint64_t n) { unrecorded_ += n; }
    // A camera sample of value X in a pixel of estimate I: s2 = (X / I)^2.
    void add_camera_sample(double s2);

    // The per-method rounds (above): a distance decision in `cell` of the round of `method`, s2 =
    // (S / I)^2 of what followed it, and the field lookups it made.
    void add_method_decision(DistanceMethod method, size_t cell, double s2, uint64_t lookups);
    // `n` events of a kind other than a distance decision in `cell` of the round of `method`.
    void add_method_event(DistanceMethod method, size_t cell, CostEvent event, uint64_t n = 1);
    // The expected extra cost (ns; negative: saved) of guided RR/splitting at a continuation point in `cell`.
    void add_method_split_cost(DistanceMethod method, size_t cell, double ns);
    // A camera sample of the round of `method` (s2 as add_camera_sample) and the decisions it made
    // (per DecisionKind / SelectionDecision).
    void add_method_camera_sample(DistanceMethod method, double s2,
                                  const std::array<uint64_t, kSelectionDecisions>& decisions);
    struct MethodMoments {
        ExactSum m;
        uint64_t count = 0;  // distance decisions (= events[Segment] = events[DistanceDecision])
        std::array<uint64_t, kCostEvents> events{};
        ExactSum split_ns, roulette_ns;  // guided splitting's expected extra cost and its roulette's savings, ns
    };
    struct MethodRound {
        ExactSum camera_moment;
        uint64_t camera_samples = 0;
        std::array<uint64_t, kSelectionDecisions> decisions{};
    };
    const MethodMoments& method_moments(DistanceMethod method, size_t cell) const {
        return methods_[cell][size_t(method)];
    }
    const MethodRound& method_round(DistanceMethod method) const { return rounds_[size_t(method)]; }

    SelectionStatistics& operator+=(const SelectionStatistics& o);

    struct Moments {
        std::array<ExactSum, kSelectionShares.size()> m;
        ExactSum current;  // sum of s2: M at the share the pilot sampled with
        uint64_t count = 0;
    };
    struct Calibration {
        ExactSum estimate, measured;
        uint64_t count = 0;
    };
    const Moments& moments(SelectionDecision d, size_t cell) const { return moments_[cell][size_t(d)]; }
    const Calibration& calibration(int stage, size_t cell) const { return calibration_[cell][size_t(stage)]; }
    uint64_t unrecorded_decisions() const { return unrecorded_; }
    uint64_t camera_samples() const { return camera_samples_; }
    double camera_moment() const { return camera_moment_.value(); }

  private:
    std::vector<std::array<Moments, kSelectionDecisions>> moments_;
    std::vector<std::array<Calibration, kSelectionStages>> calibration_;
    std::vector<std::array<MethodMoments, kDistanceMethods>> methods_;
    std::array<MethodRound, kDistanceMethods> rounds_{};
    uint64_t unrecorded_ = 0;
    uint64_t camera_samples_ = 0;
    ExactSum camera_moment_;
};

class LearnedSelection {
  public:
    static constexpr float kDefault = -1.f;  // share: keep the configured mixture
    LearnedSelection() = default;
    // Learns from the pilot's statistics; `default_share[d]`: the configured guided share of each
    // decision (what the pilot sampled with, where nothing is learned).
    static LearnedSelection fit(const SelectionStatistics& stats, const SelectionSettings& settings,
                                const std::array<float, kSelectionDecisions>& default_share);

    bool empty() const { return cells_.empty(); }
    // Whether any cell has a learned share for decision d (else every share is kDefault).
    bool learned(SelectionDecision d) const { return learned_[size_t(d)]; }
    size_t cells() const { return cells_.size(); }
    // The learned guided share in `cell` (kDefault: not learned; cell beyond the table: kDefault).
    float share(SelectionDecision d, size_t cell) const {
        return cell < cells_.size() ? cells_[cell].share[size_t(d)] : kDefault;
    }
    // The distance method chosen in `cell` (a DistanceMethod, or kMethodDefault: the configured one).
    uint8_t distance_method(size_t cell) const {
        return cell < cells_.size() ? cells_[cell].distance_method : kMethodDefault;
    }
    // Every cell of `cells` forced to `method` (the pilot's rounds), nothing else learned (volpath:
    // every share 0 and guided RR/splitting off).
    static LearnedSelection forced_method(size_t cells, DistanceMethod method);
    // Whether `cell` makes volpath's decisions (DistanceMethod::Volpath), and whether any cell does.
    bool volpath(size_t cell) const {
        return cell < cells_.size() && cells_[cell].distance_method == uint8_t(DistanceMethod::Volpath);
    }
    bool has_volpath_cells() const { return has_volpath_; }
    // Whether guided RR/splitting acts at `stage` in `cell` (true where not learned).
    bool rrs_acts(int stage, size_t cell) const {
        return cell >= cells_.size() || cells_[cell].rrs[size_t(stage)] != 0;
    }

    // Cells per decision with a learned share of 0 / > 0, and with guided RR/splitting switched off.
    struct Summary {
        std::array<uint64_t, kSelectionDecisions> unguided{}, guided{};
        std::array<double, kSelectionDecisions> mean_share{};  // over the learned cells
        uint64_t rrs_off = 0;
        std::array<uint64_t, kDistanceMethods> methods{};  // cells per chosen distance method
    };
    Summary summary() const;

    // Little-endian bytes (the prepass state carries them) and back; deserialize throws
    // std::runtime_error on a malformed buffer.
    std::string serialize() const;
    static LearnedSelection deserialize(const std::string& bytes);

    struct Cell {
        std::array<float, kSelectionDecisions> share{kDefault, kDefault, kDefault};
        std::array<uint8_t, kSelectionStages> rrs{1, 1};
        uint8_t distance_method = kMethodDefault;
    };
    const std::vector<Cell>& table() const { return cells_; }

  private:
    static Cell volpath_cell();  // every share 0, guided RR/splitting off
    void update_learned();
    std::vector<Cell> cells_;
    std::array<bool, kSelectionDecisions> learned_{};
    bool has_volpath_ = false;
};

// The cost model's estimate (ns) of `cell`'s events in the round of `method` (docs/theory.md §7.12).
double method_cell_cost(const SelectionStatistics& stats, const SelectionCosts& costs, DistanceMethod method,
                        size_t cell);
// Its estimate (ns) of a camera sample of that round with every cell on `method`.
double method_round_cost_per_sample(const SelectionStatistics& stats, const SelectionCosts& costs,
                                    DistanceMethod method);

}  // namespace volguide
