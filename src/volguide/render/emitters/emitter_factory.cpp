// Placeholder: the emitter plugins replace this with the real factory table.
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_emitter(const Properties& props) {
    props.fail_here("unsupported {} plugin '{}'", props.category(), props.type());
}

}  // namespace volguide
