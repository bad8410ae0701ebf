// The texture factory table: XML type name -> plugin.
#include "volguide/render/textures/textures.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_texture(const Properties& props) {
    if (props.type() == "checkerboard") return make_checkerboard_texture(props);
    if (props.type() == "bitmap") return make_bitmap_texture(props);
    if (props.type() == "rawconstant") return make_rawconstant_texture(props);
    if (props.type() == "mesh_attribute") return make_mesh_attribute_texture(props);
    props.fail_here("unsupported texture plugin '{}' (supported: checkerboard, bitmap, rawconstant, mesh_attribute)",
                    props.type());
}

}  // namespace volguide
