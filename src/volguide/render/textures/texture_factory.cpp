// Placeholder: the texture plugins replace this with the real factory table.
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_texture(const Properties& props) {
    props.fail_here("unsupported {} plugin '{}'", props.category(), props.type());
}

}  // namespace volguide
