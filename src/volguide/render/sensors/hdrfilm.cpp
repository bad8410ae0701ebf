#include "volguide/render/sensors/hdrfilm.h"

#include <cmath>

#include "volguide/core/log.h"
#include "volguide/core/memory.h"
#include "volguide/render/sensors/rfilters.h"

namespace volguide {

namespace {

void check_format(const Properties& props, const char* name, std::initializer_list<const char*> silent) {
    if (!props.has(name)) return;
    std::string value = props.get_string(name);
    for (const char* s : silent)
        if (value == s) return;
    warn(props.location_of(name), "hdrfilm {} '{}' is not honoured: volguide writes float32 RGB", name,
         value);
}

// What every film reads: resolution, crop window, sample_border and filter.
std::shared_ptr<Film> make_film(const Properties& props) {
    int64_t width = props.get_int("width", 768), height = props.get_int("height", 576);
    if (width <= 0 || width > 65536)
        props.fail_at("width", "film width must be in [1, 65536], got {}", width);
    if (height <= 0 || height > 65536)
        props.fail_at("height", "film height must be in [1, 65536], got {}", height);
    const uint64_t need = film_memory_bytes(width, height), have = memory_budget_bytes();
    if (have > 0 && need > have)
        props.fail_at("width", "a {}x{} film needs about {} of memory, more than {}", width, height,
                      format_bytes(need), memory_budget_description());

    // A crop window equal to the full film is harmless; anything else is not supported.
    int64_t cx = props.get_int("crop_offset_x", 0), cy = props.get_int("crop_offset_y", 0);
    int64_t cw = props.get_int("crop_width", width), ch = props.get_int("crop_height", height);
    if (cx != 0 || cy != 0 || cw != width || ch != height) {
        const char* culprit = cx != 0       ? "crop_offset_x"
                              : cy != 0     ? "crop_offset_y"
                              : cw != width ? "crop_width"
                                            : "crop_height";
        props.fail_at(culprit, "hdrfilm: crop windows are not supported");
    }

    bool sample_border = props.get_bool("sample_border", false);

    auto filters = props.children("rfilter");
    if (filters.size() > 1) fail(filters[1]->loc, "a film can only have one reconstruction filter");
    std::shared_ptr<ReconstructionFilter> filter;
    if (filters.empty()) {
        filter = std::make_shared<GaussianFilter>();  // Mitsuba's default
    } else {
        filter = std::dynamic_pointer_cast<ReconstructionFilter>(std::get<ObjectPtr>(filters[0]->value));
        if (!filter) fail(filters[0]->loc, "the <rfilter> child of hdrfilm is not a reconstruction filter");
    }
    return std::make_shared<Film>(int(width), int(height), std::move(filter), sample_border);
}

PngTonemap read_png_tonemap(const Properties& props) {
    PngTonemap t;
    const std::string method = props.get_string("tonemap_method", "gamma");
    if (method == "reinhard")
        t.method = PngTonemap::Method::reinhard;
    else if (method != "gamma")
        props.fail_at("tonemap_method", "ldrfilm: tonemap_method must be 'gamma' or 'reinhard', got '{}'", method);
    t.gamma = props.get_float("gamma", -1.f);
    if (t.gamma != -1.f && !(t.gamma > 0 && std::isfinite(t.gamma)))
        props.fail_at("gamma", "ldrfilm: gamma must be -1 (the sRGB curve) or a finite number > 0, got {}", t.gamma);
    t.exposure = props.get_float("exposure", 0.f);
    if (!std::isfinite(t.exposure)) props.fail_at("exposure", "ldrfilm: exposure must be finite");
    t.key = props.get_float("key", 0.18f);
    if (!(t.key > 0 && t.key <= 1)) props.fail_at("key", "ldrfilm: key must lie in (0, 1], got {}", t.key);
    t.burn = props.get_float("burn", 0.f);
    if (!(t.burn >= 0 && t.burn <= 1)) props.fail_at("burn", "ldrfilm: burn must lie in [0, 1], got {}", t.burn);
    // An exposure only scales the gamma method's input; key and burn are Reinhard's.
    if (t.method == PngTonemap::Method::reinhard && props.has("exposure"))
        props.fail_at("exposure", "ldrfilm: exposure applies to tonemap_method 'gamma' only (Reinhard's uses 'key')");
    if (t.method == PngTonemap::Method::gamma)
        for (const char* name : {"key", "burn"})
            if (props.has(name))
                props.fail_at(name, "ldrfilm: '{}' applies to tonemap_method 'reinhard' only", name);
    return t;
}

}  // namespace

std::shared_ptr<Film> make_hdrfilm(const Properties& props) {
    if (props.type() != "hdrfilm")
        props.fail_here("unsupported film plugin '{}' (supported: hdrfilm, ldrfilm)", props.type());
    check_format(props, "pixel_format", {"rgb", "rgba"});
    check_format(props, "component_format", {"float16", "float32"});
    check_format(props, "file_format", {"openexr", "exr"});
    return make_film(props);
}

std::shared_ptr<Film> make_ldrfilm(const Properties& props) {
    std::shared_ptr<Film> film = make_film(props);
    film->set_png_tonemap(read_png_tonemap(props));
    return film;
}

std::shared_ptr<Film> make_default_film() {
    return std::make_shared<Film>(768, 576, std::make_shared<GaussianFilter>());
}

}  // namespace volguide
