#include "volguide/guiding/guided_distance.h"

#include <algorithm>
#include <cmath>

namespace volguide {

namespace {

using namespace distance_detail;

// Below this optical thickness the truncated exponential is numerically a uniform density (2.1).
constexpr float kThinTau = 1e-6f;

// 1 - exp(-tau) per channel.
Color3 one_minus_transmittance(const Color3& sigma_t, float length) {
    return {-std::expm1(-sigma_t.r * length), -std::expm1(-sigma_t.g * length),
            -std::expm1(-sigma_t.b * length)};
}

Color3 transmittance(const Color3& sigma_t, float length) {
    return exp(sigma_t * -length);
}

}  // namespace

float sample_truncated_exponential(float sigma, float length, float u) {
    const float tau = sigma * length;
    if (tau <= kThinTau) return u * length;
    return -std::log1p(u * std::expm1(-tau)) / sigma;
}

float truncated_exponential_pdf(float sigma, float length, float x) {
    const float tau = sigma * length;
    if (tau <= kThinTau) return 1.f / length;
    return sigma * std::exp(-sigma * x) / -std::expm1(-tau);
}

DistanceStrategy choose_distance_strategy(const GuidedDistanceSettings& settings, float u) {
    if (!(u < settings.c_T)) return DistanceStrategy::Guided;
    const Color3& q = settings.channel_split;
    const float v = u / settings.c_T;
    if (v < q.r && q.r > 0.f) return DistanceStrategy::TransmittanceR;
    if (v < q.r + q.g && q.g > 0.f) return DistanceStrategy::TransmittanceG;
    if (q.b > 0.f) return DistanceStrategy::TransmittanceB;
    return q.g > 0.f ? DistanceStrategy::TransmittanceG : DistanceStrategy::TransmittanceR;
}

// ---------------------------------------------------------------------------------------------

IncrementalDistanceWalk::IncrementalDistanceWalk(const GuidedDistanceSettings& settings,
                                                 DistanceStrategy strategy)
    : settings_(settings), strategy_(strategy) {}

float IncrementalDistanceWalk::sample_in_bin(const DistanceBin& bin, const Bin& p, float u) const {
    const float sigma =
        strategy_ == DistanceStrategy::Guided ? p.sigma_bar : bin.sigma_t[channel_of(strategy_)];
    const float t = bin.t0 + sample_truncated_exponential(sigma, p.length, u);
    // Rounding may land on t1, which belongs to the next bin.
    return std::min(t, std::nextafter(bin.t1, bin.t0));
}

float IncrementalDistanceWalk::pdf_in_bin(const DistanceBin& bin, const Bin& p, float t) const {
    const auto [transmittance_part, guided_part] = pdf_parts_in_bin(bin, p, t);
    return settings_.c_T * transmittance_part + (1.f - settings_.c_T) * guided_part;
}

std::pair<float, float> IncrementalDistanceWalk::pdf_parts_in_bin(const DistanceBin& bin, const Bin& p,
                                                                  float t) const {
    const float x = t - bin.t0;
    const Color3 R_T = transmittance(tau_, 1.f), &q = settings_.channel_split;
    float transmittance_part;
    if (is_grey(bin.sigma_t)) {
        transmittance_part = (q.r * R_T.r + q.g * R_T.g + q.b * R_T.b) * p.P_T_bar *
                             truncated_exponential_pdf(bin.sigma_t.r, p.length, x);
    } else {
        const Color3 P_T = one_minus_transmittance(bin.sigma_t, p.length);
        transmittance_part = 0.f;
        for (int c = 0; c < 3; ++c)
            transmittance_part +=
                q[c] * R_T[c] * P_T[c] * truncated_exponential_pdf(bin.sigma_t[c], p.length, x);
    }
    const float guided_part = R_G_ * p.P_G * truncated_exponential_pdf(p.sigma_bar, p.length, x);
    return {transmittance_part, guided_part};
}

float IncrementalDistanceWalk::surface_probability() const {
    const auto [transmittance_part, guided_part] = surface_parts();
    return settings_.c_T * transmittance_part + (1.f - settings_.c_T) * guided_part;
}

std::pair<float, float> IncrementalDistanceWalk::surface_parts() const {
    const Color3 R_T = transmittance(tau_, 1.f), &q = settings_.channel_split;
    return {q.r * R_T.r + q.g * R_T.g + q.b * R_T.b, R_G_};
}

float incremental_distance_pdf(std::span<const DistanceBin> bins, float t,
                               const GuidedDistanceSettings& settings) {
    IncrementalDistanceWalk walk(settings);
    for (const DistanceBin& bin : bins) {
        if (!(bin.t1 > bin.t0)) continue;
        const IncrementalDistanceWalk::Bin p = walk.evaluate(bin);
        if (t >= bin.t0 && t < bin.t1) return walk.pdf_in_bin(bin, p, t);
        walk.advance(bin, p);
    }
    return 0.f;
}

float incremental_surface_probability(std::span<const DistanceBin> bins,
                                      const GuidedDistanceSettings& settings) {
    IncrementalDistanceWalk walk(settings);
    for (const DistanceBin& bin : bins)
        if (bin.t1 > bin.t0) walk.advance(bin, walk.evaluate(bin));
    return walk.surface_probability();
}

// ---------------------------------------------------------------------------------------------

TabulatedDistance::TabulatedDistance(std::span<const DistanceBin> bins, std::optional<float> surface_radiance,
                                     const GuidedDistanceSettings& settings)
    : bins_(bins), settings_(settings) {
    const size_t n = bins.size();
    float max_valid_inscattered = 0.f;
    for (const DistanceBin& b : bins)
        if (b.valid && std::isfinite(b.inscattered)) max_valid_inscattered = std::max(max_valid_inscattered, b.inscattered);

    tau_.assign(n + 1, Color3(0.f));
    sigma_bar_.resize(n);
    std::vector<double> mass(n + 1, 0.0);
    double tau_bar = 0.0;  // channel-average optical depth at the bin start
    const DistanceBin* last = nullptr;
    for (size_t k = 0; k < n; ++k) {
        const DistanceBin& b = bins[k];
        assert(std::isfinite(b.t1) && "clip the ray to the cache/medium bounds before sampling");
        const float length = std::max(0.f, b.t1 - b.t0);
        sigma_bar_[k] = scalar_sigma_t(b.sigma_t);
        tau_[k + 1] = tau_[k] + b.sigma_t * length;
        if (length > 0.f) {
            const double inscattered = b.valid ? b.inscattered : max_valid_inscattered;
            const double W =
                std::exp(-tau_bar) * b.albedo * -std::expm1(-double(sigma_bar_[k]) * length) * inscattered;
            if (std::isfinite(W))
                mass[k] = std::max(0.0, W);
            else
                ++nan_fallbacks_;
            last = &b;
        }
        tau_bar += double(sigma_bar_[k]) * length;
    }
    double L_o = 0.0;
    if (surface_radiance) {
        L_o = *surface_radiance;
    } else if (last) {
        const double T = std::exp(-double(scalar_sigma_t(last->sigma_t)) * (last->t1 - last->t0));
        if (!last->valid)
            L_o = max_valid_inscattered;
        else if (T >= kFilterMinTransmittance)
            L_o = (last->L - (1.0 - T) * last->albedo * last->inscattered) / T;
    }
    const double W_s = std::exp(-tau_bar) * L_o;
    if (std::isfinite(W_s))
        mass[n] = std::max(0.0, W_s);
    else
        ++nan_fallbacks_;

    double Z = 0.0;
    for (double m : mass) Z += m;
    guided_cdf_.resize(n + 1);
    if (Z > 0.0) {
        double c = 0.0;
        for (size_t k = 0; k <= n; ++k) guided_cdf_[k] = (c += mass[k] / Z);
        guided_surface_ = mass[n] / Z;
    } else {
        std::fill(guided_cdf_.begin(), guided_cdf_.end() - 1, 0.0);
        guided_surface_ = 1.0;
    }
    guided_cdf_[n] = 1.0;
    const Color3 T_s = exp(tau_[n] * -1.f), &q = settings_.channel_split;
    P_surf_ = settings_.c_T * (q.r * T_s.r + q.g * T_s.g + q.b * T_s.b) +
              (1.f - settings_.c_T) * float(guided_surface_);
}

int TabulatedDistance::find_bin(float t) const {
    // First bin with t1 > t (bins are contiguous and ordered).
    auto it = std::upper_bound(bins_.begin(), bins_.end(), t,
                               [](float v, const DistanceBin& b) { return v < b.t1; });
    if (it == bins_.end() || t < it->t0) return -1;
    return int(it - bins_.begin());
}

float TabulatedDistance::pdf(float t) const {
    const int k = find_bin(t);
    if (k < 0) return 0.f;
    const DistanceBin& b = bins_[size_t(k)];
    const float length = b.t1 - b.t0, x = t - b.t0;
    float transmittance_part = 0.f;
    for (int c = 0; c < 3; ++c) {
        const float P_T = -std::expm1(-b.sigma_t[c] * length);
        transmittance_part += settings_.channel_split[c] * std::exp(-tau_[size_t(k)][c]) * P_T *
                              truncated_exponential_pdf(b.sigma_t[c], length, x);
    }
    const double mass = guided_cdf_[size_t(k)] - (k > 0 ? guided_cdf_[size_t(k) - 1] : 0.0);
    const float guided_part = float(mass) * truncated_exponential_pdf(sigma_bar_[size_t(k)], length, x);
    return settings_.c_T * transmittance_part + (1.f - settings_.c_T) * guided_part;
}

DistanceSample TabulatedDistance::sample(float u, float u2, float u3) const {
    DistanceSample out;
    out.strategy = choose_distance_strategy(settings_, u);
    out.steps = int(bins_.size());
    out.nan_fallbacks = nan_fallbacks_;
    out.t = bins_.empty() ? 0.f : bins_.back().t1;
    int k = -1;
    float x = 0.f;
    if (out.strategy == DistanceStrategy::Guided) {
        const size_t n = bins_.size();
        const size_t i = size_t(std::upper_bound(guided_cdf_.begin(), guided_cdf_.end(), double(u2)) -
                                guided_cdf_.begin());
        if (i < n) {
            k = int(i);
            const DistanceBin& b = bins_[i];
            x = sample_truncated_exponential(sigma_bar_[i], b.t1 - b.t0, u3);
        }
    } else {
        // Free flight in channel c: invert the optical depth tau_c(t) = -ln(1 - u2).
        const int c = channel_of(out.strategy);
        const float tau = -std::log1p(-u2);
        auto it = std::upper_bound(tau_.begin() + 1, tau_.end(), tau,
                                   [c](float v, const Color3& d) { return v < d[c]; });
        if (it != tau_.end()) {
            k = int(it - tau_.begin()) - 1;
            const DistanceBin& b = bins_[size_t(k)];
            x = (tau - tau_[size_t(k)][c]) / b.sigma_t[c];
        }
    }
    if (k < 0) {
        out.event = DistanceEvent::Surface;
        out.pdf = P_surf_;
        return out;
    }
    const DistanceBin& b = bins_[size_t(k)];
    out.event = DistanceEvent::Medium;
    out.t = std::clamp(b.t0 + x, b.t0, std::nextafter(b.t1, b.t0));
    out.pdf = pdf(out.t);
    return out;
}

}  // namespace volguide
