// Integrator plugins by XML type name.
#include <fmt/format.h>

#include <cstdio>

#include "volguide/integrators/direct.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/integrator_configuration.h"
#include "volguide/integrators/moment.h"
#include "volguide/integrators/path.h"
#include "volguide/integrators/ptracer.h"
#include "volguide/integrators/simple_volpath.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/scene/factories.h"
#if VOLGUIDE_HAVE_OPENPGL
#include "volguide/integrators/openpgl/openpgl_volpath.h"
#endif

namespace volguide {

namespace {

std::shared_ptr<Integrator> make_integrator(const Properties& props) {
    const std::string& type = props.type();
    // prb / prbvolpath are Mitsuba 3's differentiable renderers; their forward (primal) image is
    // path's / volpath's, which is all volguide renders (no gradients).
    if (type == "path" || type == "prb") return std::make_shared<PathIntegrator>(props);
    // volpathmis (Mitsuba's spectral-MIS variant) renders the same image as volpath; volguide's
    // media already weight chromatic extinction spectrally, so both map to one integrator.
    if (type == "volpath" || type == "volpathmis" || type == "prbvolpath") return std::make_shared<VolPathIntegrator>(props);
    if (type == "direct") return std::make_shared<DirectIntegrator>(props);
    if (type == "ptracer") return std::make_shared<ParticleTracerIntegrator>(props);
    if (type == "simple_volpath") return std::make_shared<SimpleVolPathIntegrator>(props);
    if (type == "moment") return std::make_shared<MomentIntegrator>(props);
    if (type == "guided_volpath") return std::make_shared<GuidedVolPathIntegrator>(props);
    if (type == "openpgl_volpath") {
#if VOLGUIDE_HAVE_OPENPGL
        return std::make_shared<OpenPglVolPathIntegrator>(props);
#else
        props.fail_here(
            "integrator 'openpgl_volpath' is not available: volguide was built without Intel Open PGL (it is built "
            "from ../shared/third_party/openpgl-0.7.1-src.tar.gz or found as an installed openpgl CMake package "
            "when configuring; `volguide --version` says whether it is built in)");
#endif
    }
    props.fail_here("unsupported integrator plugin '{}' (supported: path, prb, volpath, volpathmis, prbvolpath, direct, ptracer, simple_volpath, guided_volpath, openpgl_volpath, moment)", type);
}

}  // namespace

ObjectPtr create_integrator(const Properties& props) {
    std::shared_ptr<Integrator> integrator = make_integrator(props);
    integrator->set_configuration(integrator_configuration(props));
    return integrator;
}

}  // namespace volguide
