#pragma once
// Mitsuba's `hg` phase function (Henyey-Greenstein), parameter g (default 0.8):
//   p(wi, wo) = (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)),  mu = dot(wo, -wi),
// so g > 0 scatters forward (wo near -wi = the ray direction). Sampling is exact (weight 1).
// The formulas work with 1 - |mu| computed without cancellation, so lobes up to |g| = 0.9999
// keep their shape and never produce NaN.
#include "volguide/core/properties.h"
#include "volguide/media/phase.h"

namespace volguide {

class HGPhase final : public PhaseFunction {
public:
    // |g| is clamped to kMaxAbsG (the XML plugin rejects |g| >= 1 instead).
    static constexpr float kMaxAbsG = 0.9999f;
    explicit HGPhase(float g);

    PhaseSample sample(const Vec3f& wi, Point2f u) const override;
    float eval(const Vec3f& wi, const Vec3f& wo) const override;
    float pdf(const Vec3f& wi, const Vec3f& wo) const override { return eval(wi, wo); }
    PhaseValue eval_pdf(const Vec3f& wi, const Vec3f& wo) const override {
        const float v = eval(wi, wo);
        return {v, v};
    }
    float mean_cosine() const override { return g_; }
    float g() const { return g_; }
    std::string to_string() const override;

private:
    float g_;
};

std::shared_ptr<PhaseFunction> make_hg_phase(const Properties& props);

}  // namespace volguide
