// Integrator plugins by XML type name.
#include <fmt/format.h>

#include <cstdio>

#include "volguide/integrators/moment.h"
#include "volguide/integrators/path.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_integrator(const Properties& props) {
    const std::string& type = props.type();
    if (type == "path") return std::make_shared<PathIntegrator>(props);
    if (type == "volpath" || type == "volpathmis") {
        // Until participating media land, a scene that reaches this point has no media (the
        // loader rejects <medium>), and volpath renders exactly what path renders.
        return std::make_shared<PathIntegrator>(props);
    }
    if (type == "moment") return std::make_shared<MomentIntegrator>(props);
    props.fail_here("unsupported integrator plugin '{}' (supported: path, volpath, volpathmis, moment)", type);
}

}  // namespace volguide
