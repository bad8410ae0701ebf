#pragma once
// The objects the module hands to Python. Python holds them by shared_ptr: an integrator taken from
// a scene and a field trained on it keep that scene alive.
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"

namespace volguide::python {

struct SceneHandle {
    std::unique_ptr<Scene> scene;
    std::string path;
    std::map<std::string, std::string> defines;
    double load_seconds = 0;
    // One job (render, training, radiance) at a time per scene: preprocessing mutates integrators,
    // and a scene's integrator is shared by every job that does not bring its own.
    std::mutex jobs;
};

struct IntegratorHandle {
    std::shared_ptr<Integrator> integrator;  // aliases the scene for a scene's own integrator
    std::shared_ptr<SceneHandle> owner;      // the scene owning it, or null for a free integrator
};

struct FieldHandle {
    std::shared_ptr<const GuidingField> field;
    std::shared_ptr<SceneHandle> scene;  // the scene it was trained on (distance_pdf's default), or null
};

}  // namespace volguide::python
