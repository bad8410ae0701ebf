// Placeholder: the integrator plugins replace this with the real factory table.
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_integrator(const Properties& props) {
    props.fail_here("unsupported {} plugin '{}'", props.category(), props.type());
}

}  // namespace volguide
