#include "volguide/integrators/integrator.h"

#include <stdexcept>

namespace volguide {

std::string Integrator::prepass_state() const {
    throw std::runtime_error("the integrator " + configuration() + " has no pre-pass to save");
}

void Integrator::use_prepass_state(const std::string&) {
    throw std::runtime_error("the integrator " + configuration() + " has no pre-pass to load");
}

}  // namespace volguide
