#pragma once
// Texture plugins. create_texture() (texture_factory.cpp) maps XML names to these.
#include <memory>
#include <string>

#include "volguide/core/image.h"
#include "volguide/core/properties.h"
#include "volguide/render/texture.h"
#include "volguide/render/textures/uv_transform.h"

namespace volguide {

// `checkerboard`: color0 (default 0.4) and color1 (default 0.2) in a 2x2 pattern per unit uv square.
std::shared_ptr<Texture> make_checkerboard_texture(const Properties& props);

enum class BitmapFilter { Nearest, Bilinear };
enum class BitmapWrap { Repeat, Mirror, Clamp };

// `bitmap` on an image already in memory (linear RGB, top row first). uv (0, 0) is the first
// pixel of the top row and v grows downwards, as Mitsuba (whose mesh loaders flip v on input).
class BitmapTexture final : public Texture {
  public:
    BitmapTexture(Image image, BitmapFilter filter, BitmapWrap wrap, UvTransform to_uv);
    Color3 eval(const SurfaceInteraction& si) const override;
    // Mitsuba returns the luminance for RGB bitmaps.
    float eval_1(const SurfaceInteraction& si) const override { return eval(si).luminance(); }
    // Mitsuba's mean of a bitmap is the average luminance (a scalar), returned as gray.
    Color3 mean() const override { return Color3(mean_); }
    // Mitsuba's: the derivative of the bilinear interpolation of the luminance (zero for `nearest`),
    // through the transpose of to_uv's 2x2 block, in texels scaled by the resolution.
    bool has_gradient() const override { return true; }
    Vec2f eval_1_grad(const SurfaceInteraction& si) const override;
    std::string to_string() const override { return "BitmapTexture[]"; }
    std::pair<int, int> resolution() const override { return {image_.width, image_.height}; }

    Color3 lookup(Vec2f uv) const;  // after to_uv

  private:
    int wrap(int value, int res) const;

    Image image_;
    BitmapFilter filter_;
    BitmapWrap wrap_;
    UvTransform to_uv_;
    float mean_ = 0.f;
};

// `rawconstant`: `value`, a float or a `<vector>` of three, used as is (no colour conversion or
// clipping: normal maps, raw parameters).
std::shared_ptr<Texture> make_rawconstant_texture(const Properties& props);

// `mesh_attribute`: `name` ("vertex_..." or "face_..."), `scale` (default 1).
std::shared_ptr<Texture> make_mesh_attribute_texture(const Properties& props);

// `bitmap` from the scene: filename (relative paths also tried next to the scene file),
// filter_type (bilinear | nearest), wrap_mode (repeat | mirror | clamp), raw, to_uv,
// format (variant | fp32: stored as float32; fp16: values rounded to half precision, as Mitsuba stores them).
std::shared_ptr<Texture> make_bitmap_texture(const Properties& props);

}  // namespace volguide
