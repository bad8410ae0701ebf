#pragma once
// Mitsuba 3 XML scenes → the render-ready Scene.
// Pipeline: XML (pugixml) → Properties records with file:line → factories → Scene.
#include <map>
#include <memory>
#include <string>

#include "volguide/core/properties.h"
#include "volguide/render/scene.h"

namespace volguide {

struct LoadOptions {
    // -D name=value overrides of <default> values; a name the scene never declares is an error.
    std::map<std::string, std::string> defines;
};

// Parses the file and instantiates every object; returns the root <scene> record whose children
// are the instantiated top-level objects. Throws InputError (file:line) on any problem.
Properties load_scene_properties(const std::string& path, const LoadOptions& options = {});

std::unique_ptr<Scene> load_scene(const std::string& path, const LoadOptions& options = {});

}  // namespace volguide
