#pragma once
// Value elements of a scene object (<integer>, <float>, <boolean>, <string>, <rgb>, <spectrum>,
// <point>, <vector>, <transform>) → typed Properties entries.
#include <string_view>

#include "volguide/core/properties.h"
#include "volguide/scene/file_resolver.h"
#include "volguide/scene/xml_element.h"

namespace volguide {

struct PropertyContext {
    const SceneParameters* params = nullptr;
    const FileResolver* resolver = nullptr;
    bool within_emitter = false;  // the enclosing object is an <emitter> (affects spectra)
};

bool is_value_tag(std::string_view tag);         // integer ... transform
bool is_transform_op_tag(std::string_view tag);  // translate, rotate, scale, matrix, lookat

// Parses one value element and adds it to `props`.
void add_value_property(const XmlElement& el, Properties& props, const PropertyContext& ctx);

// Resolves a file name (string parameter `filename`, spectrum file) against the resolver.
std::string resolve_filename(const XmlElement& el, const std::string& name, const PropertyContext& ctx);

}  // namespace volguide
