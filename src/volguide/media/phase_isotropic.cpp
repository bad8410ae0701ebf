#include "volguide/media/phase_isotropic.h"

#include "volguide/core/warp.h"

namespace volguide {

PhaseSample IsotropicPhase::sample(const Vec3f&, Point2f u) const {
    return {warp::square_to_uniform_sphere(u), InvFourPi, 1.f};
}

float IsotropicPhase::eval(const Vec3f&, const Vec3f&) const { return InvFourPi; }

std::shared_ptr<PhaseFunction> make_isotropic_phase(const Properties&) {
    return std::make_shared<IsotropicPhase>();
}

}  // namespace volguide
