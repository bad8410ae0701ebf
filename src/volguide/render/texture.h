#pragma once
// Spatially varying reflectance/roughness, looked up at a surface point.
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "volguide/core/color.h"
#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/geometry/interaction.h"

namespace volguide {

class Texture : public Object {
public:
    virtual Color3 eval(const SurfaceInteraction& si) const = 0;
    // Scalar lookup (roughness, weights): the average of the channels.
    virtual float eval_1(const SurfaceInteraction& si) const { return eval(si).average(); }
    virtual Color3 mean() const = 0;
    virtual bool is_constant() const { return false; }
    // Gradient of eval_1 with respect to (u, v), for bump mapping; textures without one (see
    // has_gradient) return zero.
    virtual bool has_gradient() const { return is_constant(); }
    virtual Vec2f eval_1_grad(const SurfaceInteraction&) const { return Vec2f(0.f, 0.f); }
    // Pixel resolution (width, height) of image textures; (1, 1) otherwise (Mitsuba's resolution()).
    virtual std::pair<int, int> resolution() const { return {1, 1}; }
};

class ConstantTexture final : public Texture {
public:
    explicit ConstantTexture(const Color3& value) : value_(value) {}
    Color3 eval(const SurfaceInteraction&) const override { return value_; }
    Color3 mean() const override { return value_; }
    bool is_constant() const override { return true; }

private:
    Color3 value_;
};

// A texture-valued parameter: a nested/referenced <texture>, or an rgb/spectrum/float value.
// With no default, a missing parameter is an input error.
std::shared_ptr<Texture> texture_param(const Properties& props, const std::string& name,
                                       std::optional<Color3> def = std::nullopt);

}  // namespace volguide
