#pragma once
// Mitsuba's `isotropic` phase function: 1 / (4 pi) for every pair of directions.
#include "volguide/core/properties.h"
#include "volguide/media/phase.h"

namespace volguide {

class IsotropicPhase final : public PhaseFunction {
public:
    IsotropicPhase() = default;
    PhaseSample sample(const Vec3f& wi, Point2f u) const override;
    float eval(const Vec3f& wi, const Vec3f& wo) const override;
    float pdf(const Vec3f& wi, const Vec3f& wo) const override { return eval(wi, wo); }
    PhaseValue eval_pdf(const Vec3f& wi, const Vec3f& wo) const override {
        const float v = eval(wi, wo);
        return {v, v};
    }
    float mean_cosine() const override { return 0.f; }
    std::string to_string() const override { return "IsotropicPhase[]"; }
};

std::shared_ptr<PhaseFunction> make_isotropic_phase(const Properties& props);

}  // namespace volguide
