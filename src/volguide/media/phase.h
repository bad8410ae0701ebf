#pragma once
// Phase functions. Convention (Mitsuba 3's): wi is the unit direction towards the previous vertex
// (wi = -ray.d); forward scattering (g > 0) sends wo close to -wi. eval() returns p(wi, wo) per
// steradian, normalised over wo; sample() returns a direction with its pdf and weight eval/pdf.
#include "volguide/core/object.h"
#include "volguide/core/vec.h"

namespace volguide {

struct PhaseSample {
    Vec3f wo;
    float pdf = 0.f;
    float weight = 0.f;  // eval / pdf (1 for exactly sampled phase functions)
};

// A phase function's value and pdf at one pair of directions (equal for exactly sampled ones).
struct PhaseValue {
    float value = 0.f;
    float pdf = 0.f;
};

class PhaseFunction : public Object {
public:
    virtual PhaseSample sample(const Vec3f& wi, Point2f u) const = 0;
    virtual float eval(const Vec3f& wi, const Vec3f& wo) const = 0;
    virtual float pdf(const Vec3f& wi, const Vec3f& wo) const { return eval(wi, wo); }
    // eval and pdf together (the guided direction decision asks for both at every guided sample):
    // exactly sampled phase functions override it with one evaluation.
    virtual PhaseValue eval_pdf(const Vec3f& wi, const Vec3f& wo) const { return {eval(wi, wo), pdf(wi, wo)}; }
    // Mean cosine g between -wi and wo (0 for isotropic): guiding picks its phase VMM with it.
    virtual float mean_cosine() const = 0;
};

}  // namespace volguide
