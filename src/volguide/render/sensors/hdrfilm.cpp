#include "volguide/render/sensors/hdrfilm.h"

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

}  // namespace

std::shared_ptr<Film> make_hdrfilm(const Properties& props) {
    if (props.type() != "hdrfilm")
        props.fail_here("unsupported film plugin '{}' (supported: hdrfilm)", props.type());
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

    check_format(props, "pixel_format", {"rgb", "rgba"});
    check_format(props, "component_format", {"float16", "float32"});
    check_format(props, "file_format", {"openexr", "exr"});
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

std::shared_ptr<Film> make_default_film() {
    return std::make_shared<Film>(768, 576, std::make_shared<GaussianFilter>());
}

}  // namespace volguide
