// Kept apart from loader.cpp so that code using only load_scene_properties (e.g. the loader
// tests) does not need the Scene implementation at link time.
#include "volguide/scene/loader.h"

#include "volguide/integrators/integrator.h"
#include "volguide/render/bsdf.h"
#include "volguide/scene/factories.h"

namespace volguide {

std::unique_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options) {
    return make_scene(load_scene_properties(path, options));
}

std::unique_ptr<Scene> make_scene(const Properties& root) {
    auto integrators = root.children("integrator");
    if (integrators.size() > 1) fail(integrators[1]->loc, "only one top-level <integrator> is supported");
    std::shared_ptr<Integrator> integrator;
    if (integrators.empty()) {
        integrator = std::dynamic_pointer_cast<Integrator>(
            create_integrator(Properties("integrator", "path", root.location())));
    } else {
        integrator = std::dynamic_pointer_cast<Integrator>(std::get<ObjectPtr>(integrators[0]->value));
        if (!integrator) fail(integrators[0]->loc, "<integrator> is not a integrator");
    }
    auto bsdf = std::dynamic_pointer_cast<BSDF>(create_bsdf(Properties("bsdf", "diffuse", root.location())));
    return std::make_unique<Scene>(root, std::move(integrator), bsdf);
}

}  // namespace volguide
