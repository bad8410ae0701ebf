// The `bitmap` plugin: parameters and image loading (through read_image of render/image_io.h).
#include <Imath/half.h>

#include <filesystem>

#include "volguide/render/image_io.h"
#include "volguide/render/textures/textures.h"

namespace volguide {

namespace {

// Mitsuba's `format`: the precision the texels are stored at. volguide stores float32, which is what
// `variant` means for the RGB variants Mitsuba's references use; `fp16` rounds every value to half.
void apply_storage_format(const Properties& props, Image& image) {
    const std::string format = props.get_string("format", "variant");
    if (format == "variant" || format == "fp32") return;
    if (format != "fp16")
        props.fail_at("format", "invalid bitmap format '{}': must be 'variant', 'fp16' or 'fp32'", format);
    for (Color3& c : image.pixels) c = Color3(float(half(c.r)), float(half(c.g)), float(half(c.b)));
}

}  // namespace

std::shared_ptr<Texture> make_rawconstant_texture(const Properties& props) {
    const Properties::Entry* e = props.find("value");
    if (!e) props.fail_here("rawconstant: missing required parameter 'value'");
    Color3 v;
    if (std::holds_alternative<Vec3f>(e->value)) {
        const Vec3f x = props.get_vec3("value");
        v = Color3(x.x, x.y, x.z);
    } else {
        v = Color3(props.get_float("value"));
    }
    if (!v.is_finite()) props.fail_at("value", "rawconstant: the value must be finite");
    return std::make_shared<ConstantTexture>(v);
}

std::shared_ptr<Texture> make_bitmap_texture(const Properties& props) {
    const std::string filename = props.get_string("filename");
    std::filesystem::path path(filename);
    if (path.is_relative() && !std::filesystem::exists(path)) {
        // Mitsuba resolves relative paths against the scene file's folder.
        std::filesystem::path scene_dir =
            std::filesystem::path(props.location_of("filename").file).parent_path();
        if (std::filesystem::exists(scene_dir / path)) path = scene_dir / path;
    }

    const std::string filter = props.get_string("filter_type", "bilinear");
    BitmapFilter f;
    if (filter == "bilinear")
        f = BitmapFilter::Bilinear;
    else if (filter == "nearest")
        f = BitmapFilter::Nearest;
    else
        props.fail_at("filter_type", "invalid filter type '{}': must be 'nearest' or 'bilinear'", filter);

    const std::string wrap = props.get_string("wrap_mode", "repeat");
    BitmapWrap w;
    if (wrap == "repeat")
        w = BitmapWrap::Repeat;
    else if (wrap == "mirror")
        w = BitmapWrap::Mirror;
    else if (wrap == "clamp")
        w = BitmapWrap::Clamp;
    else
        props.fail_at("wrap_mode", "invalid wrap mode '{}': must be 'repeat', 'mirror' or 'clamp'", wrap);

    const bool raw = props.get_bool("raw", false);
    const UvTransform to_uv = UvTransform::parse(props);
    Image image;
    try {
        image = read_image(path.string(), raw);
    } catch (const InputError& e) {
        props.fail_at("filename", "bitmap '{}': {}", path.string(), e.message());
    }
    if (image.width < 1 || image.height < 1) props.fail_at("filename", "bitmap '{}' is empty", filename);
    apply_storage_format(props, image);
    return std::make_shared<BitmapTexture>(std::move(image), f, w, to_uv);
}

}  // namespace volguide
