#pragma once
// Helpers shared by the BSDF plugins: optional/validated texture parameters and the factory
// functions of the individual plugins (one .cpp each).
#include <memory>
#include <string>

#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/render/texture.h"

namespace volguide {

// A texture parameter that must be non-negative (and finite) where it is a constant.
inline std::shared_ptr<Texture> nonnegative_texture(const Properties& props, const std::string& name,
                                                    std::optional<Color3> def = std::nullopt) {
    auto tex = texture_param(props, name, def);
    if (tex->is_constant()) {
        Color3 v = tex->mean();
        if (!v.is_finite() || v.has_negative())
            props.fail_at(name, "'{}' must be finite and non-negative (got {}, {}, {})", name, v.r, v.g, v.b);
    }
    return tex;
}

// Mitsuba only creates some modulation textures when given; nullptr stands for the constant 1.
inline std::shared_ptr<Texture> optional_texture(const Properties& props, const std::string& name) {
    return props.has(name) ? nonnegative_texture(props, name) : nullptr;
}

inline Color3 eval_or_one(const std::shared_ptr<Texture>& tex, const SurfaceInteraction& si) {
    return tex ? tex->eval(si) : Color3(1.f);
}

// Mitsuba's Texture::mean() is a scalar: the channel average for RGB values.
inline float scalar_mean(const std::shared_ptr<Texture>& tex) {
    return tex ? tex->mean().average() : 1.f;
}

ObjectPtr make_diffuse_bsdf(const Properties& props);
ObjectPtr make_dielectric_bsdf(const Properties& props);
ObjectPtr make_thin_dielectric_bsdf(const Properties& props);
ObjectPtr make_rough_dielectric_bsdf(const Properties& props);
ObjectPtr make_conductor_bsdf(const Properties& props);
ObjectPtr make_rough_conductor_bsdf(const Properties& props);
ObjectPtr make_plastic_bsdf(const Properties& props);
ObjectPtr make_rough_plastic_bsdf(const Properties& props);
ObjectPtr make_twosided_bsdf(const Properties& props);
ObjectPtr make_null_bsdf(const Properties& props);
ObjectPtr make_mask_bsdf(const Properties& props);
ObjectPtr make_blend_bsdf(const Properties& props);
ObjectPtr make_normalmap_bsdf(const Properties& props);
ObjectPtr make_bumpmap_bsdf(const Properties& props);
ObjectPtr make_principled_bsdf(const Properties& props);
ObjectPtr make_principled_thin_bsdf(const Properties& props);

}  // namespace volguide
