// `bumpmap` (Mitsuba 3): a nested BSDF evaluated in the shading frame of a surface displaced along its
// shading normal by `scale` (default 1) times a texture (its one nested texture, usually a raw bitmap):
// dp_du' = dp_du + n (scale ∂h/∂u − n·dp_du), likewise dp_dv', normal = normalize(dp_du' × dp_dv')
// turned towards the geometric normal, tangent = dp_du' made orthogonal to it. wi and wo are carried
// into that frame; a direction on opposite sides of the two frames' surfaces gives zero, as Mitsuba.
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/shading_frame_bsdf.h"

namespace volguide {

namespace {

class BumpMapBSDF final : public ShadingFrameBSDF {
  public:
    explicit BumpMapBSDF(const Properties& props) : scale_(props.get_float("scale", 1.f)) {
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
    SurfaceInteraction perturbed(const SurfaceInteraction& si) const override {
        const Vec2f g = height_->eval_1_grad(si) * scale_;
        const Vec3f& n = si.sh_frame.n;
        const Vec3f dp_du = si.dp_du + n * (g.x - dot(n, si.dp_du));
        const Vec3f dp_dv = si.dp_dv + n * (g.y - dot(n, si.dp_dv));
        Frame f;
        f.n = normalize(cross(dp_du, dp_dv));
        if (dot(si.n, f.n) < 0.f) f.n = -f.n;
        f.s = normalize(dp_du - f.n * dot(f.n, dp_du));
        f.t = cross(f.n, f.s);
        return with_frame(si, f);
    }

    float scale_;
    std::shared_ptr<Texture> height_;
};

}  // namespace

ObjectPtr make_bumpmap_bsdf(const Properties& props) {
    return std::make_shared<BumpMapBSDF>(props);
}

}  // namespace volguide
