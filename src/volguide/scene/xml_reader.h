#pragma once
// XML files → SceneGraph. Two passes over the include tree: the first loads every file and
// collects <default>s and <path>s (so defaults may be declared after their use or in included
// files), the second builds the records with every attribute substituted.
#include <string>

#include "volguide/scene/loader.h"
#include "volguide/scene/scene_graph.h"

namespace volguide {

SceneGraph read_scene_graph(const std::string& path, const LoadOptions& options);

// `volguide upgrade`: the text of a Mitsuba 0.x scene file in Mitsuba 3's form (legacy_upgrade.h),
// comments and indentation kept. Files it includes are read (their defaults and paths count) but not
// rewritten; an included 0.x file is a warning. InputError when the file is not a 0.x file.
std::string upgrade_scene_file(const std::string& path, const LoadOptions& options);

}  // namespace volguide
