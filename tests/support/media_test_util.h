#pragma once
// Helpers for media estimator tests: a procedural chromatic cloud grid and exact (quadrature)
// optical depths, transmittances and scattering integrals along a ray.
#include <cmath>
#include <memory>
#include <vector>

#include "volguide/media/heterogeneous.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/core/transform.h"
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

// The cloud of the tracking tests: rotated, scaled and moved (tracking runs in the volume's local
// coordinates), constant albedo, isotropic phase.
inline std::shared_ptr<HeterogeneousMedium> cloud_medium(int channels, const Color3& albedo, float scale) {
    Transform to_world = Transform::translate(Vec3f(-1.f, -0.6f, -0.4f)) * Transform::rotate(Vec3f(0, 0, 1), 30.f) *
                         Transform::scale(Vec3f(2.f, 1.5f, 1.f));
    auto sigma = std::make_shared<Volume>(
        VoxelGrid(procedural_cloud(24, 20, 16, channels), VolumeFilter::Trilinear, VolumeWrap::Clamp), to_world);
    auto alb = std::make_shared<Volume>(VoxelGrid(albedo), Transform());
    return std::make_shared<HeterogeneousMedium>(sigma, scale, alb, std::make_shared<IsotropicPhase>());
}

// Rays of the tracking tests through that cloud.
struct TestRay {
    Ray ray;
    float tmax;
};

inline std::vector<TestRay> test_rays() {
    // The cloud's centre is near (-0.5, 0.55, 0.15): through it, starting and ending inside, oblique.
    return {{Ray(Point3f(-3.f, 0.55f, 0.15f), normalize(Vec3f(1.f, 0.f, 0.01f))), Infinity},
            {Ray(Point3f(-0.5f, 0.3f, 0.1f), normalize(Vec3f(-0.3f, 1.f, 0.2f))), 0.6f},
            {Ray(Point3f(-1.5f, -0.8f, -1.f), normalize(Vec3f(1.f, 1.35f, 1.15f))), Infinity}};
}

// Quadrature length of a test ray: up to tmax or well past the medium's box.
inline double profile_length(const Medium& m, const TestRay& r) { return std::isinf(r.tmax) ? 10.0 : double(r.tmax); }

}  // namespace volguide::test
