// Sensor, film, reconstruction filter and sampler plugins by XML type name.
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/render/sensors/orthographic.h"
#include "volguide/render/sensors/perspective.h"
#include "volguide/render/sensors/rfilters.h"
#include "volguide/render/sensors/sampler_settings.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_sensor(const Properties& props) {
    if (props.type() == "perspective" || props.type() == "thinlens") return std::make_shared<PerspectiveCamera>(props);
    if (props.type() == "orthographic") return std::make_shared<OrthographicCamera>(props);
    props.fail_here("unsupported sensor plugin '{}' (supported: perspective, thinlens, orthographic)", props.type());
}

ObjectPtr create_film(const Properties& props) {
    if (props.type() == "ldrfilm") return make_ldrfilm(props);
    return make_hdrfilm(props);
}

ObjectPtr create_rfilter(const Properties& props) {
    if (props.type() == "box") return std::make_shared<BoxFilter>(props);
    if (props.type() == "tent") return std::make_shared<TentFilter>(props);
    if (props.type() == "gaussian") return std::make_shared<GaussianFilter>(props);
    if (props.type() == "mitchell") return std::make_shared<MitchellFilter>(props);
    if (props.type() == "catmullrom") return make_catmull_rom();
    if (props.type() == "lanczos") return std::make_shared<LanczosFilter>(props);
    props.fail_here(
        "unsupported rfilter plugin '{}' (supported: box, tent, gaussian, mitchell, catmullrom, lanczos)",
        props.type());
}

ObjectPtr create_sampler(const Properties& props) {
    return std::make_shared<SamplerSettings>(props);
}

}  // namespace volguide
