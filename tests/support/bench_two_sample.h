#pragma once
// A per-pixel two-sample test of two renders of a benchmark scene (bench/scenes/) at 32×24: each
// render's mean and per-sample variance (--variance), then per pixel-channel a z-test with a
// Bonferroni-corrected level (family-wise 1 %; at most 0.5 % of the channels may exceed it) and a
// test of the image means (4 standard errors). Shared by the tests that compare a guided
// integrator (guided_volpath, openpgl_volpath) with volpath.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/render/image_io.h"

namespace volguide::test {

struct BenchRender {
    Image mean, var;
    int spp;
};

// bench/scenes/<scene>.xml at 32×24 with `spp` and `seed`; `extra`: further CLI arguments (-D ...).
inline BenchRender render_bench_scene(const TempDir& dir, const std::string& scene, const std::string& name, int spp,
                                      int seed, const std::vector<std::string>& extra) {
    std::vector<std::string> cmd = {"render", source_dir() + "/bench/scenes/" + scene + ".xml", "-D", "width=32",
                                    "-D", "height=24", "--spp", std::to_string(spp), "--seed", std::to_string(seed),
                                    "--variance", "--quiet", "-o", dir.file(name + ".exr")};
    cmd.insert(cmd.end(), extra.begin(), extra.end());
    CliResult r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return {read_image(dir.file(name + ".exr")), read_image(dir.file(name + "_var.exr")), spp};
}

// The z with P(|Z| > z) = level, by bisection.
inline double two_sided_z(double level) {
    double lo = 0.0, hi = 20.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// `a` (the unguided reference render) and `b` estimate the same image.
inline void expect_same_expectation(const BenchRender& a, const BenchRender& b, const std::string& scene,
                                    const std::string& label_a, const std::string& label_b) {
    ASSERT_EQ(a.mean.pixels.size(), b.mean.pixels.size());
    const double n = 3.0 * double(a.mean.pixels.size());
    const double z_crit = two_sided_z(1.0 - std::pow(1.0 - 0.01, 1.0 / n));
    long failed = 0;
    double sum_a = 0, sum_b = 0, var_a = 0, var_b = 0;
    for (size_t i = 0; i < a.mean.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double x = a.mean.pixels[i][c], y = b.mean.pixels[i][c];
            const double vx = a.var.pixels[i][c] / a.spp, vy = b.var.pixels[i][c] / b.spp;
            sum_a += x;
            sum_b += y;
            var_a += vx;
            var_b += vy;
            // Float floor: sky pixels seen through an empty stretch of the cloud's grid are exact for
            // volpath (variance 0) and carry rounding of guided tracking weights (~1e-5 relative).
            const double se = std::sqrt(vx + vy) + 1e-5 * std::max(std::abs(x), std::abs(y));
            if (se > 0.0 ? std::abs(x - y) / se > z_crit : x != y) ++failed;
        }
    EXPECT_LE(double(failed), 0.005 * n) << scene << ": " << failed << " of " << n
                                         << " pixel-channels differ beyond z = " << z_crit;
    const double se_mean = std::sqrt(var_a + var_b) / n;
    EXPECT_LT(std::abs(sum_a - sum_b) / n, 4.0 * se_mean) << scene << ": image means " << sum_a / n << " ("
                                                           << label_a << ") vs " << sum_b / n << " (" << label_b
                                                           << ") ± " << se_mean;
}

}  // namespace volguide::test
