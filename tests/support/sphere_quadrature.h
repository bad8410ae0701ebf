#pragma once
// Deterministic quadrature over the unit sphere for concentrated integrands (vMF lobes up to
// kappa = 32000, HG peaks). Spherical coordinates about a chosen axis: theta in geometrically
// graded panels starting at `scale` (the angular width of the peak), Gauss-Legendre in each
// panel, and the periodic trapezoid rule in phi (spectrally accurate for smooth integrands).
#include <cmath>
#include <vector>

#include "volguide/core/frame.h"
#include "volguide/core/vec.h"

namespace volguide::test {

struct GaussLegendre {
    std::vector<double> x, w;  // nodes and weights on [-1, 1]
    explicit GaussLegendre(int n) : x(n), w(n) {
        for (int i = 0; i < n; ++i) {
            double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = 0.0;
                for (int j = 0; j < n; ++j) {
                    double p2 = p1;
                    p1 = p0;
                    p0 = ((2.0 * j + 1.0) * z * p1 - j * p2) / (j + 1.0);
                }
                dp = n * (z * p0 - p1) / (z * z - 1.0);
                double dz = p0 / dp;
                z -= dz;
                if (std::abs(dz) < 1e-15) break;
            }
            x[i] = z;
            w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        }
    }
};

// Integral of f(w) over S^2; f takes a float unit direction (as the code under test does).
template <typename F>
double integrate_sphere(F&& f, const Vec3f& axis, double scale, int n_phi = 64, int n_gauss = 24) {
    static const GaussLegendre gl24(24);
    GaussLegendre own(n_gauss == 24 ? 1 : n_gauss);
    const GaussLegendre& gl = n_gauss == 24 ? gl24 : own;
    Frame frame(normalize(axis));
    std::vector<double> breaks{0.0};
    for (double t = std::min(scale, M_PI) / 8.0; t < M_PI; t *= 2.0) breaks.push_back(t);
    breaks.push_back(M_PI);
    double total = 0.0;
    for (size_t p = 0; p + 1 < breaks.size(); ++p) {
        double a = breaks[p], b = breaks[p + 1];
        for (size_t i = 0; i < gl.x.size(); ++i) {
            double theta = 0.5 * (a + b) + 0.5 * (b - a) * gl.x[i];
            double ring = 0.0;
            for (int k = 0; k < n_phi; ++k) {
                double phi = 2.0 * M_PI * (k + 0.5) / n_phi;
                Vec3d local(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta));
                Vec3d world = Vec3d(frame.s) * local.x + Vec3d(frame.t) * local.y + Vec3d(frame.n) * local.z;
                ring += f(Vec3f(normalize(world)));
            }
            total += 0.5 * (b - a) * gl.w[i] * std::sin(theta) * ring * (2.0 * M_PI / n_phi);
        }
    }
    return total;
}

}  // namespace volguide::test
