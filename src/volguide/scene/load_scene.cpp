// Kept apart from loader.cpp so that code using only load_scene_properties (e.g. the loader
// tests) does not need the Scene implementation at link time.
#include "volguide/scene/loader.h"

#include "volguide/integrators/integrator.h"
#include "volguide/integrators/path.h"
#include "volguide/render/bsdf.h"
#include "volguide/scene/factories.h"

namespace volguide {

namespace {

// Whether any medium is referenced: the sensor's, a shape's interior or exterior, a point emitter's.
bool scene_has_media(const Scene& scene) {
    if (scene.sensor().medium()) return true;
    for (const auto& shape : scene.shapes())
        if (shape->interior_medium() || shape->exterior_medium()) return true;
    for (const auto& emitter : scene.emitters())
        if (emitter->medium()) return true;
    return false;
}

// A light tracer's own requirements, reported at its <integrator> line: connections to a pinhole
// sensor, and surfaces only (its paths never enter a medium, so a medium would be skipped silently).
void check_light_tracer(const Scene& scene, const SourceLocation& loc) {
    if (!scene.sensor().supports_connections())
        fail(loc, "a light tracer (ptracer) connects its paths to a pinhole sensor: 'perspective' without an "
                  "aperture");
    if (scene_has_media(scene))
        fail(loc,
             "ptracer renders surfaces only (its light paths do not enter media) and this scene has "
             "participating media: render it with volpath or guided_volpath");
}

}  // namespace

std::unique_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options) {
    return make_scene(load_scene_properties(path, options));
}

std::unique_ptr<Scene> make_scene(const Properties& root) {
    // Mitsuba's default integrator is `path` with its defaults; it is not the file's, so it carries
    // no configuration (distributed parts record the file's integrator, none here).
    auto integrators = root.children("integrator");
    std::shared_ptr<Integrator> integrator = std::make_shared<PathIntegrator>(PathSettings{});
    if (!integrators.empty())
        integrator = std::dynamic_pointer_cast<Integrator>(std::get<ObjectPtr>(integrators[0]->value));
    auto bsdf = std::dynamic_pointer_cast<BSDF>(create_bsdf(Properties("bsdf", "diffuse", root.location())));
    // The scene checks its shapes, emitters and sensor first; the integrator's errors come after.
    auto scene = std::make_unique<Scene>(root, integrator, bsdf);
    if (integrators.size() > 1) fail(integrators[1]->loc, "only one top-level <integrator> is supported");
    if (!integrator) fail(integrators[0]->loc, "<integrator> is not a integrator");
    if (integrator->traces_from_emitters()) check_light_tracer(*scene, integrators[0]->loc);
    return scene;
}

}  // namespace volguide
