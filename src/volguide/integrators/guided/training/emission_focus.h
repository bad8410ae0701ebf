#pragma once
// Focused photon emission (Jensen's projection maps, adapted): a pilot set of photons finds which
// parts of each emitter's emission domain send light into a medium, and the photon pass then emits
// mostly from there. A sun over a closed room sends ~0.5 % of its photons through the window; all
// the others would only cost time, and the field of the room would get 200x fewer samples.
//
// Each emitter's focused 2-D sample (u_pos for emitters with an extent or at infinity — the position
// on its surface or on the bounding sphere's disk —, u_dir for point-like emitters) is cut into
// kResolution² cells. A cell is "useful" when a pilot photon from it deposited a medium collision, or
// when no pilot photon came from it (unknown, kept); useful cells are dilated by one cell (partly
// covered cells at the edge of a window). Emission picks a cell with probability
//   p_c = (1 - defensive) · useful_c / Σ useful + defensive / kResolution²
// and a uniform point inside it; the photon's flux is divided by p_c · kResolution² (the density of
// the focused u against the uniform one), so the photon estimates stay unbiased — every cell keeps a
// positive probability. The field only shapes probabilities anyway; unbiasedness keeps its fluence
// comparable across regions.
#include <cstdint>
#include <vector>

#include "volguide/core/distribution.h"
#include "volguide/core/vec.h"

namespace volguide {

class Emitter;

// Which of sample_ray's two 2-D samples the focus acts on.
enum class FocusedSample { Position, Direction };
FocusedSample focused_sample(const Emitter& emitter);

// Per-emitter pilot counts, filled by one thread (a batch) and merged.
struct EmissionPilot {
    static constexpr int kResolution = 64;
    static constexpr int kCells = kResolution * kResolution;
    explicit EmissionPilot(size_t emitters = 0);
    void record(size_t emitter, Point2f u, bool deposited);
    EmissionPilot& operator+=(const EmissionPilot& o);
    static int cell_of(Point2f u);

    std::vector<uint32_t> photons;    // [emitter * kCells + cell]
    std::vector<uint32_t> deposited;  // photons of the cell that deposited at least one collision
};

class EmissionFocus {
public:
    static constexpr int kResolution = EmissionPilot::kResolution;
    static constexpr int kCells = EmissionPilot::kCells;

    EmissionFocus() = default;  // no focus: uniform, weight 1
    EmissionFocus(const EmissionPilot& pilot, float defensive);

    bool active() const { return !per_emitter_.empty(); }
    // Maps a uniform 2-D sample of `emitter` to the focused one (u_cell picks the cell) and returns
    // the factor for the photon's flux (1 / (p_c · kCells)).
    float warp(size_t emitter, float u_cell, Point2f& u) const;
    // Probability that the focused sample of `emitter` lands in the useful cells (statistics).
    float useful_fraction(size_t emitter) const { return per_emitter_[emitter].useful_mass; }

private:
    struct PerEmitter {
        DiscreteDistribution cells;  // empty: uniform (nothing learned)
        float useful_mass = 1.f;
    };
    std::vector<PerEmitter> per_emitter_;
};

}  // namespace volguide
