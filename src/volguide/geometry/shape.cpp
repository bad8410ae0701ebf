#include "volguide/geometry/shape.h"

#include "volguide/render/bsdf.h"
#include "volguide/media/medium.h"
#include "volguide/render/emitter.h"

namespace volguide {

void Shape::init_common(const Properties& props) {
    auto bsdfs = props.children("bsdf");
    if (bsdfs.size() > 1)
        fail(bsdfs[1]->loc, "shape '{}' has more than one BSDF (at most one is allowed)", props.type());
    if (!bsdfs.empty()) {
        auto obj = std::get<ObjectPtr>(bsdfs[0]->value);
        bsdf_ = std::dynamic_pointer_cast<BSDF>(obj);
        if (!bsdf_) fail(bsdfs[0]->loc, "shape '{}': the <bsdf> child is not a BSDF", props.type());
    }

    auto emitters = props.children("emitter");
    if (emitters.size() > 1)
        fail(emitters[1]->loc, "shape '{}' has more than one emitter (at most one is allowed)", props.type());
    if (!emitters.empty()) {
        auto obj = std::get<ObjectPtr>(emitters[0]->value);
        emitter_ = std::dynamic_pointer_cast<Emitter>(obj);
        if (!emitter_)
            fail(emitters[0]->loc, "shape '{}': the <emitter> child is not an emitter", props.type());
        if (!(emitter_->flags() & emitter_flags::Surface))
            fail(emitters[0]->loc, "shape '{}': only area emitters can be attached to a shape", props.type());
        emitter_->set_shape(this);
    }
    interior_ = get_object_as<Medium>(props, "interior");
    exterior_ = get_object_as<Medium>(props, "exterior");
}

// Area sample converted to solid angle at the reference point (Mitsuba's Shape::sample_direction).
DirectionSample Shape::sample_direction(const Interaction& ref, Point2f u) const {
    PositionSample ps = sample_position(u);
    DirectionSample ds;
    ds.p = ps.p;
    ds.n = ps.n;
    ds.uv = ps.uv;
    ds.emitter = emitter_.get();
    Vec3f d = ps.p - ref.p;
    float dist2 = squared_norm(d);
    ds.dist = std::sqrt(dist2);
    ds.d = ds.dist > 0.f ? d / ds.dist : Vec3f(0.f);
    float cos_light = absdot(ds.d, ds.n);
    ds.pdf = (cos_light != 0.f && ds.dist > 0.f) ? ps.pdf * dist2 / cos_light : 0.f;
    return ds;
}

float Shape::pdf_direction(const Interaction& ref, const DirectionSample& ds) const {
    PositionSample ps{ds.p, ds.n, ds.uv, 0.f};
    float cos_light = absdot(ds.d, ds.n);
    return cos_light != 0.f ? pdf_position(ps) * ds.dist * ds.dist / cos_light : 0.f;
}

}  // namespace volguide
