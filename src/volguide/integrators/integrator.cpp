#include "volguide/integrators/integrator.h"

#include <stdexcept>

namespace volguide {

std::string Integrator::prepass_state() const {
    throw std::runtime_error("the integrator " + configuration() + " has no pre-pass to save");
}

void Integrator::use_prepass_state(const std::string&) {
    throw std::runtime_error("the integrator " + configuration() + " has no pre-pass to load");
}

void Integrator::restore_render_state(const std::string& bytes) {
    if (!bytes.empty())
        throw std::runtime_error("the integrator " + configuration() + " keeps no render state, but the checkpoint has " +
                                 std::to_string(bytes.size()) + " bytes of it");
}

}  // namespace volguide
