// Placeholder: the sensor/film plugins replace this with the real factory table.
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_sensor(const Properties& props) { props.fail_here("unsupported sensor plugin '{}'", props.type()); }
ObjectPtr create_film(const Properties& props) { props.fail_here("unsupported film plugin '{}'", props.type()); }
ObjectPtr create_rfilter(const Properties& props) { props.fail_here("unsupported rfilter plugin '{}'", props.type()); }
ObjectPtr create_sampler(const Properties& props) { props.fail_here("unsupported sampler plugin '{}'", props.type()); }

}  // namespace volguide
