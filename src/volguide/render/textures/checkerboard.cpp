#include <cmath>

#include "volguide/render/textures/textures.h"

namespace volguide {

namespace {

class Checkerboard final : public Texture {
  public:
    explicit Checkerboard(const Properties& props)
        : color0_(texture_param(props, "color0", Color3(0.4f))),
          color1_(texture_param(props, "color1", Color3(0.2f))),
          to_uv_(UvTransform::parse(props)) {}

    Color3 eval(const SurfaceInteraction& si) const override {
        return first_color(si) ? color0_->eval(si) : color1_->eval(si);
    }
    // Mitsuba keeps a legacy convention for scalar lookups: the two colours are swapped.
    float eval_1(const SurfaceInteraction& si) const override {
        return first_color(si) ? color1_->eval_1(si) : color0_->eval_1(si);
    }
    Color3 mean() const override { return (color0_->mean() + color1_->mean()) * 0.5f; }
    std::string to_string() const override { return "Checkerboard[]"; }

  private:
    // color0 where both fractional coordinates are on the same side of 1/2.
    bool first_color(const SurfaceInteraction& si) const {
        const Vec2f uv = to_uv_.apply(si.uv);
        const bool mx = uv.x - std::floor(uv.x) > 0.5f, my = uv.y - std::floor(uv.y) > 0.5f;
        return mx == my;
    }

    std::shared_ptr<Texture> color0_, color1_;
    UvTransform to_uv_;
};

}  // namespace

std::shared_ptr<Texture> make_checkerboard_texture(const Properties& props) {
    return std::make_shared<Checkerboard>(props);
}

}  // namespace volguide
