#pragma once
// The fingerprint of a scene as rendered: the scene file's bytes and the -D values (sorted), so two
// processes with the same file and the same -D render the same scene. Files the scene includes or
// references (meshes, volumes, textures) are not read: change their names, or the scene file, when
// they change (docs/distributed.md).
#include <map>
#include <string>

namespace volguide {

// Throws InputError naming the file when it cannot be read.
std::string scene_fingerprint(const std::string& path, const std::map<std::string, std::string>& defines);

}  // namespace volguide
