#include "volguide/integrators/moment.h"

namespace volguide {

MomentIntegrator::MomentIntegrator(const Properties& props) {
    auto children = props.children("integrator");
    if (children.size() != 1)
        props.fail_here("the moment integrator needs exactly one nested <integrator> (got {})", children.size());
    nested_ = std::dynamic_pointer_cast<Integrator>(std::get<ObjectPtr>(children[0]->value));
    if (!nested_) fail(children[0]->loc, "moment: the nested object is not an integrator");
    if (nested_->traces_from_emitters())
        fail(children[0]->loc, "moment: a light tracer (ptracer) has no per-sample values to take moments of");
}

}  // namespace volguide
