#include "volguide/render/texture.h"

#include <variant>

namespace volguide {

std::shared_ptr<Texture> texture_param(const Properties& props, const std::string& name,
                                       std::optional<Color3> def) {
    const Properties::Entry* e = props.find(name);
    if (!e) {
        if (!def) props.fail_here("{} '{}': missing required parameter '{}'", props.category(), props.type(), name);
        return std::make_shared<ConstantTexture>(*def);
    }
    if (std::holds_alternative<ObjectPtr>(e->value)) {
        auto tex = get_object_as<Texture>(props, name);
        return tex;
    }
    return std::make_shared<ConstantTexture>(props.get_color(name));
}

}  // namespace volguide
