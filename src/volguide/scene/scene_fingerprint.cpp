#include "volguide/scene/scene_fingerprint.h"

#include <fstream>
#include <sstream>

#include "volguide/core/error.h"
#include "volguide/core/fingerprint.h"

namespace volguide {

std::string scene_fingerprint(const std::string& path, const std::map<std::string, std::string>& defines) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(SourceLocation{path, 0}, "cannot open the scene file");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    std::string text = bytes.str();
    for (const auto& [name, value] : defines) text += std::string(1, '\0') + name + "=" + value;  // map: sorted
    return fingerprint(text);
}

}  // namespace volguide
