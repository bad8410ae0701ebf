#pragma once
// A 1-D ray through piecewise-constant media with known in-scattered radiance per segment and a
// surface at its end (docs/theory.md §14.7): the exact solution of the VRE along the ray, and the guided
// distance sampler's bins filled with exact or perturbed estimates.
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/guiding/guided_distance.h"

namespace volguide::test {

struct AnalyticSegment {
    double t0, t1;
    Color3 sigma_t, sigma_s;
    Color3 inscattered;  // in-scattered radiance L_i, constant in the segment
};

struct AnalyticRay {
    std::vector<AnalyticSegment> segments;  // contiguous, from t = 0
    Color3 L_surface;                       // L_o of the surface at the end of the last segment

    double end() const { return segments.back().t1; }

    // Exact L(d_k, omega) per channel (k = 0..N, L(d_N) = L_o), by the VRE backwards over each
    // segment: L(d_k) = (sigma_s / sigma_t)(1 - T_k) L_i,k + T_k L(d_{k+1}).
    std::vector<std::array<double, 3>> incident_at_starts() const {
        std::vector<std::array<double, 3>> L(segments.size() + 1);
        for (int c = 0; c < 3; ++c) L.back()[size_t(c)] = L_surface[c];
        for (size_t k = segments.size(); k-- > 0;) {
            const AnalyticSegment& s = segments[k];
            for (int c = 0; c < 3; ++c) {
                const double st = s.sigma_t[c], T = std::exp(-st * (s.t1 - s.t0));
                const double in =
                    st > 0 ? double(s.sigma_s[c]) / st * (1.0 - T) : double(s.sigma_s[c]) * (s.t1 - s.t0);
                L[k][size_t(c)] = in * s.inscattered[c] + T * L[k + 1][size_t(c)];
            }
        }
        return L;
    }

    int segment_at(double t) const {
        for (size_t k = 0; k < segments.size(); ++k)
            if (t >= segments[k].t0 && t < segments[k].t1) return int(k);
        return -1;
    }

    // T(0, t) in channel c.
    double transmittance(double t, int c) const {
        double tau = 0.0;
        for (const AnalyticSegment& s : segments) {
            if (t <= s.t0) break;
            tau += double(s.sigma_t[c]) * (std::min(t, s.t1) - s.t0);
        }
        return std::exp(-tau);
    }

    // One-sample estimate of L(0) in channel c for a distance sample (docs/theory.md (7.6)).
    double estimate(const DistanceSample& d, int c) const {
        if (d.event == DistanceEvent::Surface) return transmittance(end(), c) * L_surface[c] / d.pdf;
        const AnalyticSegment& s = segments[size_t(segment_at(d.t))];
        return transmittance(d.t, c) * s.sigma_s[c] * s.inscattered[c] / d.pdf;
    }

    // Channel average of the above: the quantity the scalar (channel-average) estimates describe.
    double estimate_average(const DistanceSample& d) const {
        return (estimate(d, 0) + estimate(d, 1) + estimate(d, 2)) / 3.0;
    }
    double L0_average() const {
        const auto L = incident_at_starts();
        return (L[0][0] + L[0][1] + L[0][2]) / 3.0;
    }

    // Bins with exact proxies and the channel averages of the exact estimates, each optionally
    // multiplied by a factor (noise): perturb(k, which) with which 0 = L_i, 1 = L.
    std::vector<DistanceBin> bins(const std::function<float(size_t, int)>& perturb = {}) const {
        const auto L = incident_at_starts();
        std::vector<DistanceBin> out;
        for (size_t k = 0; k < segments.size(); ++k) {
            const AnalyticSegment& s = segments[k];
            DistanceBin b;
            b.t0 = float(s.t0);
            b.t1 = float(s.t1);
            b.sigma_t = s.sigma_t;
            b.albedo = s.sigma_t.average() > 0.f ? s.sigma_s.average() / s.sigma_t.average() : 0.f;
            b.inscattered = s.inscattered.average();
            b.L = float((L[k][0] + L[k][1] + L[k][2]) / 3.0);
            if (perturb) {
                b.inscattered *= perturb(k, 0);
                b.L *= perturb(k, 1);
            }
            out.push_back(b);
        }
        return out;
    }

    // Calls a bin source that hands out `bins` in order and counts how many were pulled.
    struct Source {
        const std::vector<DistanceBin>* bins;
        size_t next = 0;
        bool operator()(DistanceBin& b) {
            if (next >= bins->size()) return false;
            b = (*bins)[next++];
            return true;
        }
    };
};

// The 6-bin ray of the tests: piecewise-constant grey coefficients, in-scattered radiance and a lit
// surface (or its chromatic variant).
inline AnalyticRay six_bin_ray(bool chromatic = false) {
    AnalyticRay r;
    const double d[7] = {0.0, 0.4, 0.9, 1.7, 2.0, 3.1, 3.6};
    const float st[6] = {0.5f, 1.2f, 0.3f, 1.5f, 0.4f, 0.6f};
    const float alb[6] = {0.9f, 0.5f, 0.99f, 0.7f, 0.8f, 0.95f};
    const float li[6] = {0.3f, 2.0f, 0.05f, 1.1f, 0.6f, 0.2f};
    for (int k = 0; k < 6; ++k) {
        Color3 sigma_t(st[k]);
        if (chromatic) sigma_t = Color3(st[k] * 2.5f, st[k], st[k] * 0.2f);
        r.segments.push_back(
            {d[k], d[k + 1], sigma_t, sigma_t * alb[k], Color3(li[k], li[k] * 0.8f, li[k] * 1.3f)});
    }
    r.L_surface = Color3(1.5f, 1.2f, 0.9f);
    return r;
}

// Distance-sampler settings in one call: c_T, p_max, the filter weight A and the denominator of the
// guided probability (default: the paper's, which the oracles of §14.7-14.8 are written for).
inline GuidedDistanceSettings settings(float c_T, float p_max, float A,
                                       DistanceDenominator denominator = DistanceDenominator::Incident,
                                       Color3 channel_split = Color3(1.f / 3.f)) {
    GuidedDistanceSettings s;
    s.c_T = c_T;
    s.p_max = p_max;
    s.filter_A = A;
    s.denominator = denominator;
    s.channel_split = channel_split;
    return s;
}

}  // namespace volguide::test
