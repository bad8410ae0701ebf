#pragma once
// Table of Henyey-Greenstein fits by zonal vMF mixtures over |g| (docs/theory.md §4.3). The data lives in
// phase_vmm_table.cpp, generated offline by tools/gen_phase_vmm_table.cpp (see its header comment
// for the command); phase_vmm.h interpolates it.
#include <array>

#include "volguide/vmm/phase_vmm_fit.h"

namespace volguide {

struct PhaseVmmTableEntry {
    float g = 0.f;
    std::array<float, kPhaseVmmMaxLobes> weight{};  // lobes sorted by decreasing kappa
    std::array<float, kPhaseVmmMaxLobes> kappa{};
    std::array<float, kPhaseVmmMaxLobes> mean_cosine{};  // A3(kappa), interpolated at lookup
};

inline constexpr int kPhaseVmmTableEntries = 128;

struct PhaseVmmTable {
    int lobes = 0;
    float max_g = 0.f;  // entry i is at g = i * max_g / (entries - 1)
    std::array<PhaseVmmTableEntry, kPhaseVmmTableEntries> entries{};
};

extern const PhaseVmmTable kHgPhaseVmmTable;

}  // namespace volguide
