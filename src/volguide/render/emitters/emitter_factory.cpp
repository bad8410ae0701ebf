// The emitter factory table: Mitsuba 3's plugin names.
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_emitter(const Properties& props) {
    const std::string& type = props.type();
    if (type == "area") return make_area_emitter(props);
    if (type == "point") return make_point_emitter(props);
    if (type == "spot") return make_spot_emitter(props);
    if (type == "projector") return make_projector_emitter(props);
    if (type == "directional") return make_directional_emitter(props);
    if (type == "constant") return make_constant_emitter(props);
    if (type == "envmap") return make_envmap_emitter(props);
    props.fail_here("unsupported {} plugin '{}' (supported: area, point, spot, directional, constant, envmap, projector)",
                    props.category(), props.type());
}

}  // namespace volguide
