// `bumpmap` (Mitsuba 3): a nested BSDF evaluated in the shading frame of a surface displaced along its
// shading normal by `scale` (default 1) times a texture (its one nested texture, usually a raw bitmap):
// dp_du' = dp_du + n (scale ∂h/∂u − n·dp_du), likewise dp_dv', normal = normalize(dp_du' × dp_dv')
// turned towards the geometric normal, tangent = dp_du made orthogonal to it. The flip of invalid
// normals, the frame change and the shadowing term: ShadingFrameBSDF. One departure: Mitsuba 3 makes
// the tangent from the world-space dp_du's components as if they were shading-frame ones; here dp_du
// is carried into the shading frame first (only an anisotropic nested BSDF can tell).
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/shading_frame_bsdf.h"

namespace volguide {

namespace {

class BumpMapBSDF final : public ShadingFrameBSDF {
  public:
    explicit BumpMapBSDF(const Properties& props) : ShadingFrameBSDF(props), scale_(props.get_float("scale", 1.f)) {
        auto bsdfs = props.children("bsdf");
        if (bsdfs.size() != 1) props.fail_here("bumpmap: exactly one nested BSDF is required, got {}", bsdfs.size());
        nested_ = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(bsdfs[0]->value));
        if (!nested_) props.fail_at(bsdfs[0]->name, "bumpmap: nested object is not a BSDF");
        auto textures = props.children("texture");
        if (textures.size() != 1)
            props.fail_here("bumpmap: exactly one nested texture is required, got {}", textures.size());
        height_ = std::dynamic_pointer_cast<Texture>(std::get<ObjectPtr>(textures[0]->value));
        if (!height_ || !height_->has_gradient())
            props.fail_at(textures[0]->name, "bumpmap: the texture must be a bitmap (it needs a gradient)");
        if (!std::isfinite(scale_)) props.fail_at("scale", "bumpmap: scale must be finite");
        flags_ = nested_->flags();
    }

    std::string to_string() const override { return "BumpMap[]"; }

  private:
    Vec3f local_normal(const SurfaceInteraction& si) const override {
        const Vec2f g = height_->eval_1_grad(si) * scale_;
        const Vec3f& n = si.sh_frame.n;
        const Vec3f dp_du = si.dp_du + n * (g.x - dot(n, si.dp_du));
        const Vec3f dp_dv = si.dp_dv + n * (g.y - dot(n, si.dp_dv));
        Vec3f bumped = normalize(cross(dp_du, dp_dv));
        if (dot(si.n, bumped) < 0.f) bumped = -bumped;
        return si.to_local(bumped);
    }
    Vec3f local_tangent(const SurfaceInteraction& si) const override { return si.to_local(si.dp_du); }

    float scale_;
    std::shared_ptr<Texture> height_;
};

}  // namespace

ObjectPtr make_bumpmap_bsdf(const Properties& props) {
    return std::make_shared<BumpMapBSDF>(props);
}

}  // namespace volguide
