// The explicit table from XML object tags to the factories of factories.h.
#include "volguide/scene/factories.h"
#include "volguide/scene/loader.h"

namespace volguide {

ObjectPtr create_object(const std::string& tag, const Properties& props) {
    if (tag == "bsdf") return create_bsdf(props);
    if (tag == "texture") return create_texture(props);
    if (tag == "emitter") return create_emitter(props);
    if (tag == "shape") return create_shape(props);
    if (tag == "sensor") return create_sensor(props);
    if (tag == "film") return create_film(props);
    if (tag == "rfilter") return create_rfilter(props);
    if (tag == "sampler") return create_sampler(props);
    if (tag == "integrator") return create_integrator(props);
    if (tag == "medium") return create_medium(props);
    if (tag == "phase") return create_phase(props);
    if (tag == "volume") return create_volume(props);
    props.fail_here("unknown object category <{}>", tag);
}

}  // namespace volguide
