// The media factory table: XML type name -> plugin, for <medium>, <phase> and <volume>.
#include "volguide/media/heterogeneous.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_hg.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/media/volume.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_medium(const Properties& props) {
    if (props.type() == "homogeneous") return make_homogeneous_medium(props);
    if (props.type() == "heterogeneous") return make_heterogeneous_medium(props);
    props.fail_here("unsupported medium plugin '{}' (supported: homogeneous, heterogeneous)", props.type());
}
ObjectPtr create_phase(const Properties& props) {
    if (props.type() == "isotropic") return make_isotropic_phase(props);
    if (props.type() == "hg") return make_hg_phase(props);
    props.fail_here("unsupported phase function plugin '{}' (supported: isotropic, hg)", props.type());
}
ObjectPtr create_volume(const Properties& props) {
    if (props.type() == "constvolume") return make_const_volume(props);
    if (props.type() == "gridvolume") return make_grid_volume(props);
    props.fail_here("unsupported volume plugin '{}' (supported: constvolume, gridvolume)", props.type());
}

}  // namespace volguide
