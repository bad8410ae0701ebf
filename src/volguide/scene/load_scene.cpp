// Kept apart from loader.cpp so that code using only load_scene_properties (e.g. the loader
// tests) does not need the Scene implementation at link time.
#include "volguide/scene/loader.h"

namespace volguide {

std::unique_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options) {
    Properties root = load_scene_properties(path, options);
    return std::make_unique<Scene>(root);
}

}  // namespace volguide
