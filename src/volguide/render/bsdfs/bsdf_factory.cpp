// The BSDF factory table: XML type name -> plugin.
#include <string_view>

#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_bsdf(const Properties& props) {
    struct Entry {
        std::string_view name;
        ObjectPtr (*make)(const Properties&);
    };
    static constexpr Entry kTable[] = {
        {"diffuse", make_diffuse_bsdf},
        {"dielectric", make_dielectric_bsdf},
        {"thindielectric", make_thin_dielectric_bsdf},
        {"roughdielectric", make_rough_dielectric_bsdf},
        {"conductor", make_conductor_bsdf},
        {"roughconductor", make_rough_conductor_bsdf},
        {"plastic", make_plastic_bsdf},
        {"roughplastic", make_rough_plastic_bsdf},
        {"twosided", make_twosided_bsdf},
        {"null", make_null_bsdf},
        {"mask", make_mask_bsdf},
        {"normalmap", make_normalmap_bsdf},
        {"bumpmap", make_bumpmap_bsdf},
        {"principled", make_principled_bsdf},
        {"principledthin", make_principled_thin_bsdf},
        {"blendbsdf", make_blend_bsdf},
    };
    for (const Entry& e : kTable)
        if (props.type() == e.name) return e.make(props);
    props.fail_here(
        "unsupported bsdf plugin '{}' (supported: diffuse, dielectric, thindielectric, roughdielectric, "
        "conductor, roughconductor, plastic, roughplastic, twosided, null, mask, normalmap, bumpmap, principled, "
        "principledthin, blendbsdf)",
        props.type());
}

}  // namespace volguide
