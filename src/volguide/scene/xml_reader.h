#pragma once
// XML files → SceneGraph. Two passes over the include tree: the first loads every file and
// collects <default>s and <path>s (so defaults may be declared after their use or in included
// files), the second builds the records with every attribute substituted.
#include <string>

#include "volguide/scene/loader.h"
#include "volguide/scene/scene_graph.h"

namespace volguide {

SceneGraph read_scene_graph(const std::string& path, const LoadOptions& options);

}  // namespace volguide
