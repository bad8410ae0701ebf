#include "volguide/integrators/guided/training/emission_focus.h"

#include <algorithm>

#include "volguide/render/emitter.h"

namespace volguide {

FocusedSample focused_sample(const Emitter& emitter) {
    // Point and spot lights have a single position: only their direction decides where light goes.
    return (emitter.flags() & emitter_flags::DeltaPosition) ? FocusedSample::Direction : FocusedSample::Position;
}

EmissionPilot::EmissionPilot(size_t emitters) : photons(emitters * kCells, 0), deposited(emitters * kCells, 0) {}

int EmissionPilot::cell_of(Point2f u) {
    const int x = std::clamp(int(u.x * kResolution), 0, kResolution - 1);
    const int y = std::clamp(int(u.y * kResolution), 0, kResolution - 1);
    return y * kResolution + x;
}

void EmissionPilot::record(size_t emitter, Point2f u, bool deposit) {
    const size_t i = emitter * kCells + size_t(cell_of(u));
    ++photons[i];
    if (deposit) ++deposited[i];
}

EmissionPilot& EmissionPilot::operator+=(const EmissionPilot& o) {
    if (photons.empty()) return *this = o;
    for (size_t i = 0; i < photons.size() && i < o.photons.size(); ++i) {
        photons[i] += o.photons[i];
        deposited[i] += o.deposited[i];
    }
    return *this;
}

EmissionFocus::EmissionFocus(const EmissionPilot& pilot, float defensive) {
    const size_t emitters = pilot.photons.size() / kCells;
    per_emitter_.resize(emitters);
    for (size_t e = 0; e < emitters; ++e) {
        const uint32_t* photons = &pilot.photons[e * kCells];
        const uint32_t* deposited = &pilot.deposited[e * kCells];
        // Useful: deposited, or unknown (no pilot photon); then dilated by one cell.
        std::vector<uint8_t> useful(kCells, 0), dilated(kCells, 0);
        for (int c = 0; c < kCells; ++c) useful[size_t(c)] = photons[c] == 0 || deposited[c] > 0;
        for (int y = 0; y < kResolution; ++y)
            for (int x = 0; x < kResolution; ++x) {
                if (!useful[size_t(y * kResolution + x)]) continue;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx >= 0 && yy >= 0 && xx < kResolution && yy < kResolution)
                            dilated[size_t(yy * kResolution + xx)] = 1;
                    }
            }
        const int count = int(std::count(dilated.begin(), dilated.end(), uint8_t(1)));
        // Nothing useful (the emitter reaches no medium) or everything: stay uniform.
        if (count == 0 || count == kCells) continue;
        std::vector<float> weights(kCells);
        const float useful_weight = (1.f - defensive) / float(count), floor = defensive / float(kCells);
        for (int c = 0; c < kCells; ++c) weights[size_t(c)] = (dilated[size_t(c)] ? useful_weight : 0.f) + floor;
        per_emitter_[e].cells = DiscreteDistribution(weights);
        per_emitter_[e].useful_mass = (1.f - defensive) + defensive * float(count) / float(kCells);
    }
}

float EmissionFocus::warp(size_t emitter, float u_cell, Point2f& u) const {
    if (emitter >= per_emitter_.size() || per_emitter_[emitter].cells.empty()) return 1.f;
    const DiscreteDistribution& cells = per_emitter_[emitter].cells;
    const size_t c = cells.sample(u_cell);
    const float x = float(c % kResolution), y = float(c / kResolution);
    // Keep u inside [0, 1) even where u * (1/64) rounds up.
    u = Point2f(std::min((x + u.x) / float(kResolution), 0x1.fffffep-1f),
                std::min((y + u.y) / float(kResolution), 0x1.fffffep-1f));
    return 1.f / (cells.pmf(c) * float(kCells));
}

}  // namespace volguide
