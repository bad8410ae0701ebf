// `normalmap` (Mitsuba 3): a nested BSDF evaluated in a shading frame whose normal is read from the
// `normalmap` texture (RGB in [0, 1] → 2·rgb − 1, in the surface's shading frame; usually a raw
// bitmap) and whose tangent is dp_du made orthogonal to it (Gram-Schmidt). wi and wo are carried into
// that frame; a direction on opposite sides of the two frames' surfaces gives zero, as Mitsuba.
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/shading_frame_bsdf.h"

namespace volguide {

namespace {

class NormalMapBSDF final : public ShadingFrameBSDF {
  public:
    explicit NormalMapBSDF(const Properties& props) : normals_(texture_param(props, "normalmap")) {
        auto children = props.children("bsdf");
        if (children.size() != 1)
            props.fail_here("normalmap: exactly one nested BSDF is required, got {}", children.size());
        nested_ = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[0]->value));
        if (!nested_) props.fail_at(children[0]->name, "normalmap: nested object is not a BSDF");
        flags_ = nested_->flags();
    }

    std::string to_string() const override { return "NormalMap[]"; }

  private:
    SurfaceInteraction perturbed(const SurfaceInteraction& si) const override {
        const Color3 c = normals_->eval(si);
        const Vec3f n_local(2.f * c.r - 1.f, 2.f * c.g - 1.f, 2.f * c.b - 1.f);
        Frame f;
        f.n = normalize(si.to_world(n_local));
        f.s = normalize(si.dp_du - f.n * dot(f.n, si.dp_du));
        f.t = cross(f.n, f.s);
        return with_frame(si, f);
    }

    std::shared_ptr<Texture> normals_;
};

}  // namespace

ObjectPtr make_normalmap_bsdf(const Properties& props) {
    return std::make_shared<NormalMapBSDF>(props);
}

}  // namespace volguide
