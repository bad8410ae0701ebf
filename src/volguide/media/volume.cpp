#include "volguide/media/volume.h"

#include <fmt/format.h>

namespace volguide {

Volume::Volume(VoxelGrid grid, const Transform& to_world)
    : grid_(std::move(grid)), to_world_(to_world), to_local_(to_world.inverse_matrix()) {
    for (int i = 0; i < 8; ++i)
        bbox_.expand(to_world.apply_point(Point3f(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1))));
}

std::string Volume::to_string() const {
    return fmt::format("Volume[res = {}x{}x{}, channels = {}, max = {}]", grid_.res(0), grid_.res(1), grid_.res(2),
                       grid_.channels(), grid_.max_value());
}

std::shared_ptr<Volume> make_const_volume(const Properties& props) {
    const Color3 value = props.get_color("value", Color3(1.f));
    if (!value.is_finite()) props.fail_at("value", "constvolume: the value must be finite");
    return std::make_shared<Volume>(VoxelGrid(value), props.get_transform("to_world"));
}

std::shared_ptr<Volume> volume_param(const Properties& props, const std::string& name, std::optional<Color3> def) {
    const Properties::Entry* e = props.find(name);
    if (!e) {
        if (!def) props.fail_here("{} '{}': missing required parameter '{}'", props.category(), props.type(), name);
        return std::make_shared<Volume>(VoxelGrid(*def), Transform());
    }
    if (std::holds_alternative<ObjectPtr>(e->value)) {
        auto vol = get_object_as<Volume>(props, name);
        return vol;
    }
    const Color3 c = props.get_color(name);
    if (!c.is_finite()) props.fail_at(name, "parameter '{}' must be finite", name);
    return std::make_shared<Volume>(VoxelGrid(c), Transform());
}

}  // namespace volguide
