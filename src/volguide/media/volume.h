#pragma once
// Volume data sources (Mitsuba 3's `constvolume` and `gridvolume`): a VoxelGrid over the local
// unit cube [0,1]^3 placed in the world by `to_world` (Mitsuba: without use_grid_bbox the grid
// spans the unit cube under to_world; with it, the file's bounding box under to_world). A constant
// volume is a 1x1x1 grid, so its bbox is also the unit cube under to_world, exactly as in Mitsuba
// (this is where a heterogeneous medium with a constant sigma_t exists).
#include <memory>
#include <optional>

#include "volguide/core/bbox.h"
#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/core/transform.h"
#include "volguide/media/affine.h"
#include "volguide/media/voxel_grid.h"

namespace volguide {

class Volume final : public Object {
public:
    // `to_world` maps the local unit cube to the world.
    Volume(VoxelGrid grid, const Transform& to_world);

    Color3 eval(const Point3f& p_world) const { return grid_.lookup(to_local_.point(p_world)); }
    const VoxelGrid& grid() const { return grid_; }
    const Affine3f& to_local() const { return to_local_; }
    const Transform& to_world() const { return to_world_; }
    // World-space bounds of the transformed unit cube.
    const BBox3f& bbox() const { return bbox_; }
    float max_value() const { return grid_.max_value(); }
    float min_value() const { return grid_.min_value(); }
    bool is_constant() const { return grid_.is_constant(); }
    std::string to_string() const override;

private:
    VoxelGrid grid_;
    Transform to_world_;
    Affine3f to_local_;
    BBox3f bbox_;
};

std::shared_ptr<Volume> make_const_volume(const Properties& props);
std::shared_ptr<Volume> make_grid_volume(const Properties& props);

// A volume-valued parameter: a nested/referenced <volume>, or a float/rgb/spectrum value (which
// becomes a constvolume with the identity transform, as Mitsuba's props.volume() does).
// With no default, a missing parameter is an input error.
std::shared_ptr<Volume> volume_param(const Properties& props, const std::string& name,
                                     std::optional<Color3> def = std::nullopt);

}  // namespace volguide
