// Generates src/volguide/vmm/phase_vmm_table.cpp: Henyey-Greenstein fits by K zonal vMF lobes at
// g_i = i * max_g / (N - 1), i = 0..N-1 (docs/theory.md §4.2-4.3). The sweep runs from max_g down to
// g_1. Candidates per entry: the best of 10 random starts, a warm start from the neighbour entry,
// and the neighbour with its mean cosines scaled by g / g_next. Among the candidates whose RMS log
// residual is within 1e-4 of the best, the one closest to the neighbour is kept: for small g the
// objective is nearly flat (HG is nearly uniform) and this keeps the lobes on one continuous
// branch, which the interpolation between entries needs.
//
// Usage (from the repository root, after building the target gen_phase_vmm_table):
//   build/gen_phase_vmm_table --lobes 3 --max-g 0.99 > src/volguide/vmm/phase_vmm_table.cpp
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "float_literal.h"
#include "volguide/vmm/phase_vmm_table.h"
#include "volguide/vmm/vmf.h"

using namespace volguide;

static std::string literal(double x) { return float_literal(x, 8); }

int main(int argc, char** argv) {
    int lobes = 3;
    double max_g = 0.99;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--lobes"))
            lobes = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--max-g"))
            max_g = std::atof(argv[i + 1]);
        else {
            std::fprintf(stderr, "usage: %s [--lobes K] [--max-g G]\n", argv[0]);
            return 2;
        }
    }
    if (lobes < 1 || lobes > kPhaseVmmMaxLobes || !(max_g > 0.0 && max_g < 1.0)) {
        std::fprintf(stderr, "need 1 <= K <= %d and 0 < max-g < 1\n", kPhaseVmmMaxLobes);
        return 2;
    }
    const int n = kPhaseVmmTableEntries;
    std::printf("// GENERATED FILE, do not edit. Regenerate from the repository root with\n");
    std::printf("//   cmake --build build --target gen_phase_vmm_table\n");
    std::printf(
        "//   build/gen_phase_vmm_table --lobes %d --max-g %g > src/volguide/vmm/phase_vmm_table.cpp\n",
        lobes, max_g);
    std::printf("// Henyey-Greenstein fits by %d zonal vMF lobes (docs/theory.md §4.2), lobes sorted by kappa.\n",
                lobes);
    std::printf(
        "// Columns: g, weights, kappas, mean cosines A3(kappa). Entry 0 (g = 0) is isotropic: kappa 0\n");
    std::printf("// with entry 1's weights, so that interpolation towards g = 0 only moves the kappas.\n");
    std::printf("#include \"volguide/vmm/phase_vmm_table.h\"\n\nnamespace volguide {\n\n");
    std::printf("// clang-format off\nconst PhaseVmmTable kHgPhaseVmmTable = {%d, %s, {{\n", lobes,
                literal(max_g).c_str());
    HgFitSettings settings;
    settings.lobes = lobes;
    std::array<ZonalFit, kPhaseVmmTableEntries> fits;
    // Distance between two fits in the interpolated coordinates (weights, mean cosines).
    auto distance = [&](const ZonalFit& a, const ZonalFit& b) {
        double d = 0.0;
        for (int j = 0; j < lobes; ++j)
            d += std::abs(a.weight[j] - b.weight[j]) +
                 std::abs(vmf_mean_cosine(a.kappa[j]) - vmf_mean_cosine(b.kappa[j]));
        return d;
    };
    for (int i = n - 1; i >= 1; --i) {
        double g = i * max_g / (n - 1);
        fits[i] = fit_hg_zonal(g, settings);
        if (i < n - 1) {
            const ZonalFit& next = fits[i + 1];
            HgFitSettings warm_only = settings;
            warm_only.starts = 0;
            ZonalFit warm = fit_hg_zonal(g, warm_only, &next);
            // The neighbour with every mean cosine scaled by g / g_next (exact to first order in g).
            ZonalFit scaled = next;
            double ratio = g / ((i + 1) * max_g / (n - 1));
            for (int j = 0; j < lobes; ++j)
                scaled.kappa[j] = vmf_kappa_from_mean_cosine(vmf_mean_cosine(next.kappa[j]) * ratio, 1e6);
            scaled.rms_log = hg_fit_rms_log(g, scaled, settings);
            scaled.mean_cosine = 0.0;
            for (int j = 0; j < lobes; ++j)
                scaled.mean_cosine += scaled.weight[j] * vmf_mean_cosine(scaled.kappa[j]);
            // Among near-optimal candidates (RMS within 1e-4 of the best), keep the one closest to
            // the neighbour, so the entries form one continuous branch.
            double best_rms = std::min({fits[i].rms_log, warm.rms_log, scaled.rms_log});
            ZonalFit chosen = fits[i];
            double chosen_distance = 1e300;
            for (const ZonalFit* c : {&fits[i], &warm, &scaled}) {
                if (c->rms_log > best_rms + 1e-4) continue;
                double d = distance(*c, next);
                if (d < chosen_distance) chosen = *c, chosen_distance = d;
            }
            fits[i] = chosen;
        }
        std::fprintf(stderr, "g %.4f rms %.4f mean cosine %.5f\n", g, fits[i].rms_log, fits[i].mean_cosine);
    }
    fits[0] = fits[1];
    for (int j = 0; j < lobes; ++j) fits[0].kappa[j] = 0.0;
    auto list = [&](const std::array<double, kPhaseVmmMaxLobes>& v, bool a3) {
        std::string s = "{";
        for (int j = 0; j < kPhaseVmmMaxLobes; ++j) {
            double x = j < lobes ? (a3 ? vmf_mean_cosine(v[j]) : v[j]) : 0.0;
            s += (j ? ", " : "") + literal(x);
        }
        return s + "}";
    };
    for (int i = 0; i < n; ++i) {
        double g = i * max_g / (n - 1);
        std::printf("    {%s, %s, %s, %s},\n", literal(g).c_str(), list(fits[i].weight, false).c_str(),
                    list(fits[i].kappa, false).c_str(), list(fits[i].kappa, true).c_str());
    }
    std::printf("}}};\n// clang-format on\n\n}  // namespace volguide\n");
    return 0;
}
