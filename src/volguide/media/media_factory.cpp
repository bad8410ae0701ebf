// Placeholder: the media plugins replace this with the real factory table.
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_medium(const Properties& props) {
    props.fail_here("<medium type=\"{}\">: media are not supported yet", props.type());
}
ObjectPtr create_phase(const Properties& props) {
    props.fail_here("<phase type=\"{}\">: media are not supported yet", props.type());
}
ObjectPtr create_volume(const Properties& props) {
    props.fail_here("<volume type=\"{}\">: media are not supported yet", props.type());
}

}  // namespace volguide
