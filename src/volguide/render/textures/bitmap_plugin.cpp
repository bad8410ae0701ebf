// The `bitmap` plugin: parameters and image loading (through read_image of render/image_io.h).
#include <filesystem>

#include "volguide/render/image_io.h"
#include "volguide/render/textures/textures.h"

namespace volguide {

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
    return std::make_shared<BitmapTexture>(std::move(image), f, w, to_uv);
}

}  // namespace volguide
