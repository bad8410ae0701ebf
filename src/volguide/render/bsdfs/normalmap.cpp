// `normalmap` (Mitsuba 3): a nested BSDF evaluated in a shading frame whose normal is read from the
// `normalmap` texture (RGB in [0, 1] → 2·rgb − 1, relative to the surface's shading frame; usually a
// raw bitmap) and whose tangent is the shading frame's own tangent made orthogonal to it, as Mitsuba
// builds it. The flip of invalid normals, the frame change and the shadowing term: ShadingFrameBSDF.
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/shading_frame_bsdf.h"

namespace volguide {

namespace {

class NormalMapBSDF final : public ShadingFrameBSDF {
  public:
    explicit NormalMapBSDF(const Properties& props)
        : ShadingFrameBSDF(props), normals_(texture_param(props, "normalmap")) {
        auto children = props.children("bsdf");
        if (children.size() != 1)
            props.fail_here("normalmap: exactly one nested BSDF is required, got {}", children.size());
        nested_ = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[0]->value));
        if (!nested_) props.fail_at(children[0]->name, "normalmap: nested object is not a BSDF");
        flags_ = nested_->flags();
    }

    std::string to_string() const override { return "NormalMap[]"; }

  private:
    Vec3f local_normal(const SurfaceInteraction& si) const override {
        const Color3 c = normals_->eval(si);
        return Vec3f(2.f * c.r - 1.f, 2.f * c.g - 1.f, 2.f * c.b - 1.f);
    }
    Vec3f local_tangent(const SurfaceInteraction&) const override { return Vec3f(1.f, 0.f, 0.f); }

    std::shared_ptr<Texture> normals_;
};

}  // namespace

ObjectPtr make_normalmap_bsdf(const Properties& props) {
    return std::make_shared<NormalMapBSDF>(props);
}

}  // namespace volguide
