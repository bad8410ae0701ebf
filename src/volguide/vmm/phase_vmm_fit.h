#pragma once
// Offline fit of a Henyey-Greenstein phase function by K <= 4 zonal vMF lobes (docs/theory.md §4.2):
// minimise sum_n [ln(f_HG(cos t_n) + eps) - ln(sum_j w_j v(cos t_n; kappa_j) + eps)]^2 over a grid
// of angles, eps = 1e-4 max f_HG, weights softmax-parameterised, log kappa as parameters,
// Levenberg-Marquardt with analytic Jacobian, multi-start plus an optional warm start.
// Used by tools/gen_phase_vmm_table to generate phase_vmm_table.cpp; not used at render time.
#include <array>
#include <cstdint>

namespace volguide {

inline constexpr int kPhaseVmmMaxLobes = 4;

struct ZonalFit {
    int lobes = 0;
    std::array<double, kPhaseVmmMaxLobes> weight{};  // sorted by decreasing kappa
    std::array<double, kPhaseVmmMaxLobes> kappa{};
    double rms_log = 0.0;      // RMS of the log residual over the grid
    double mean_cosine = 0.0;  // sum_j w_j A3(kappa_j); HG's is g
};

struct HgFitSettings {
    int lobes = 3;
    int grid = 2001;  // uniform angles on [0, pi] (plus a refinement near 0 for g > 0.95)
    int starts = 10;  // random starts, kappa log-uniform in [0.05, 5 / (1 - g)^2]
    int max_iterations = 2000;
    double epsilon = 1e-4;  // relative to max f_HG
    uint64_t seed = 1;
};

// HG density per unit solid angle at cos(angle to the forward axis) (docs/theory.md §1.1).
double hg_density(double g, double cos_theta);

// Best fit for 0 < g < 1 (the fit is symmetric: flip the axis for g < 0). `warm_start`, when
// given, is tried first (keeps the parameters continuous along a sweep over g).
ZonalFit fit_hg_zonal(double g, const HgFitSettings& settings = {}, const ZonalFit* warm_start = nullptr);

// RMS log residual of a given fit on the settings' grid (the objective, normalised).
double hg_fit_rms_log(double g, const ZonalFit& fit, const HgFitSettings& settings = {});

}  // namespace volguide
