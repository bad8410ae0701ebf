#pragma once
// The scene as read from XML, before any plugin exists: one record per object element with its
// value parameters and its child objects (nested or referenced by id), in file order.
#include <map>
#include <string>
#include <vector>

#include "volguide/core/properties.h"

namespace volguide {

struct SceneGraph {
    struct Child {
        int node = -1;       // index of a nested object, or -1 for a reference
        std::string ref_id;  // for <ref id="..">
        std::string name;    // parameter name in the parent ("" = unnamed)
        SourceLocation loc;  // of the nested element or of the <ref>
    };
    struct Node {
        std::string tag;   // factory category: bsdf, shape, ... ("scene" for the root)
        Properties props;  // value parameters; child objects are added at instantiation
        std::vector<Child> children;
    };

    std::vector<Node> nodes;         // nodes[0] is the root <scene>
    std::map<std::string, int> ids;  // id (or alias) → node index
};

}  // namespace volguide
