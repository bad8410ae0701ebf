#pragma once
// Helpers for media estimator tests: a procedural chromatic cloud grid and exact (quadrature)
// optical depths, transmittances and scattering integrals along a ray.
#include <cmath>
#include <memory>
#include <vector>

#include "volguide/media/heterogeneous.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/media/volume.h"

namespace volguide::test {

// Smooth blobs with empty regions; channel c is scaled by (1, 0.6, 0.25) and shifted so the
// channels differ in shape, not just in magnitude.
inline GridData procedural_cloud(int nx, int ny, int nz, int channels) {
    GridData g;
    g.nx = nx, g.ny = ny, g.nz = nz, g.channels = channels;
    g.bbox = BBox3f(Point3f(0.f), Point3f(1.f));
    g.values.resize(size_t(nx) * ny * nz * channels);
    const float weights[3] = {1.f, 0.6f, 0.25f};
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) {
                const float u = (x + 0.5f) / nx, v = (y + 0.5f) / ny, w = (z + 0.5f) / nz;
                for (int c = 0; c < channels; ++c) {
                    const float cx = 0.45f + 0.1f * c, cy = 0.5f, cz = 0.55f - 0.05f * c;
                    const float r2 = (u - cx) * (u - cx) + (v - cy) * (v - cy) + (w - cz) * (w - cz);
                    float val = std::exp(-r2 / 0.06f) + 0.3f * std::sin(9.f * u + 2.f * c) * std::sin(7.f * v) *
                                                            std::cos(5.f * w);
                    val = std::max(val - 0.15f, 0.f);  // empty space around the cloud
                    g.values[((size_t(z) * ny + y) * nx + x) * channels + c] = weights[c] * val;
                }
            }
    return g;
}

// Fine midpoint quadrature along ray.o + t ray.d, t in [0, len].
struct RayProfile {
    int n = 0;
    double len = 0;
    std::vector<double> tau[3];      // optical depth at the end of step i
    std::vector<double> sigma_s[3];  // at the midpoint of step i
    std::vector<double> tmid;

    RayProfile(const Medium& m, const Ray& ray, double length, int steps = 40000) : n(steps), len(length) {
        double acc[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) tau[c].resize(n), sigma_s[c].resize(n);
        tmid.resize(n);
        const double dt = len / n;
        for (int i = 0; i < n; ++i) {
            tmid[i] = (i + 0.5) * dt;
            MediumCoefficients mc = m.eval(ray(float(tmid[i])));
            for (int c = 0; c < 3; ++c) {
                acc[c] += mc.sigma_t[c] * dt;
                tau[c][i] = acc[c];
                sigma_s[c][i] = mc.sigma_s[c];
            }
        }
    }
    double total_tau(int c) const { return tau[c].back(); }
    // Optical depth at t (linear within a step).
    double tau_at(int c, double t) const {
        const double x = t / len * n;
        const int i = std::clamp(int(x), 0, n - 1);
        const double before = i > 0 ? tau[c][i - 1] : 0.0;
        return before + (tau[c][i] - before) * std::clamp(x - i, 0.0, 1.0);
    }
    // int_0^len T_c(t) sigma_s,c(t) f(t) dt
    template <typename F>
    double scatter_integral(int c, F f) const {
        double sum = 0.0;
        const double dt = len / n;
        for (int i = 0; i < n; ++i) {
            const double tau_mid = (i > 0 ? tau[c][i - 1] : 0.0) * 0.5 + tau[c][i] * 0.5;
            sum += std::exp(-tau_mid) * sigma_s[c][i] * f(tmid[i]) * dt;
        }
        return sum;
    }
};

}  // namespace volguide::test
