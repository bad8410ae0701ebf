// The `gridvolume` plugin: Mitsuba .vol files (and, as volguide's extension, OpenVDB files
// selected by the .vdb extension with the `grid` parameter naming the grid, default "density").
#include <cmath>
#include <limits>
#include <filesystem>

#include "volguide/core/log.h"
#include "volguide/media/grid_data.h"
#include "volguide/media/volume.h"

namespace volguide {

namespace {

std::string resolve(const Properties& props, const std::string& filename) {
    std::filesystem::path path(filename);
    if (path.is_relative() && !std::filesystem::exists(path)) {
        // Mitsuba resolves relative paths against the scene file's folder.
        auto dir = std::filesystem::path(props.location_of("filename").file).parent_path();
        if (std::filesystem::exists(dir / path)) path = dir / path;
    }
    return path.string();
}

bool has_vdb_extension(const std::string& filename) {
    std::string ext = std::filesystem::path(filename).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".vdb";
}

// Densities this close to zero from below are float noise (tools write -0, negative denormals such as
// -1e-45 and rounding residue such as -1.28e-38 for empty voxels), which Mitsuba 0.6 renders as 0. The
// bound is absolute: a density of 1e-20 changes the optical depth along a path of length d by
// 1e-20 * scale * d, invisible in a float transmittance (whose resolution is 6e-8) unless scale * d
// exceeds 1e12, far outside any scene's range; a relative bound would instead call a clearly negative
// voxel of a dense grid noise.
constexpr float kNegativeNoise = 1e-20f;

// Reads the noise as 0, with one warning for the file; a clearly negative value is left for the
// caller's error.
void read_negative_noise_as_zero(const Properties& props, const std::string& path, std::vector<float>& values) {
    size_t noise = 0;
    for (float& v : values)
        if (std::signbit(v) && v >= -kNegativeNoise) {
            v = 0.f;
            ++noise;
        }
    if (noise > 0)
        warn(props.location_of("filename"),
             "gridvolume \"{}\": {} negative value(s) of magnitude at most {} (float noise) read as 0", path, noise,
             kNegativeNoise);
}

}  // namespace

std::shared_ptr<Volume> make_grid_volume(const Properties& props) {
    const std::string filter_str = props.get_string("filter_type", "trilinear");
    VolumeFilter filter;
    if (filter_str == "trilinear")
        filter = VolumeFilter::Trilinear;
    else if (filter_str == "nearest")
        filter = VolumeFilter::Nearest;
    else
        props.fail_at("filter_type", "gridvolume: invalid filter type \"{}\", must be \"nearest\" or \"trilinear\"",
                      filter_str);

    const std::string wrap_str = props.get_string("wrap_mode", "clamp");
    VolumeWrap wrap;
    if (wrap_str == "clamp")
        wrap = VolumeWrap::Clamp;
    else if (wrap_str == "repeat")
        wrap = VolumeWrap::Repeat;
    else if (wrap_str == "mirror")
        wrap = VolumeWrap::Mirror;
    else
        props.fail_at("wrap_mode", "gridvolume: invalid wrap mode \"{}\", must be \"clamp\", \"repeat\" or \"mirror\"",
                      wrap_str);

    // In RGB variants Mitsuba applies no conversion to 3-channel data, raw or not; `accel` only
    // selects CUDA hardware interpolation. Both are accepted and have no effect here either.
    props.get_bool("raw", false);
    props.get_bool("accel", true);

    const std::string filename = props.get_string("filename");
    const std::string path = resolve(props, filename);
    const bool vdb = has_vdb_extension(path);
    if (!vdb && props.has("grid"))
        props.fail_at("grid", "gridvolume: 'grid' selects a grid of an OpenVDB (.vdb) file, not of \"{}\"", filename);
    GridData data;
    try {
        data = vdb ? read_vdb_file(path, props.get_string("grid", "density")) : read_vol_file(path);
    } catch (const InputError& e) {
        props.fail_at("filename", "gridvolume: {}", e.message());
    }
    if (data.channels != 1 && data.channels != 3)
        props.fail_at("filename", "gridvolume \"{}\": {} channels (only 1 or 3 are supported)", path, data.channels);
    if (data.nx < 1 || data.ny < 1 || data.nz < 1)
        props.fail_at("filename", "gridvolume \"{}\": empty grid ({}x{}x{})", path, data.nx, data.ny, data.nz);
    if (data.values.size() != size_t(data.nx) * data.ny * data.nz * data.channels)
        props.fail_at("filename", "gridvolume \"{}\": wrong number of values", path);
    read_negative_noise_as_zero(props, path, data.values);
    for (size_t i = 0; i < data.values.size(); ++i) {
        const float v = data.values[i];
        if (!std::isfinite(v) || v < 0.f) {
            const size_t voxel = i / data.channels;
            props.fail_at("filename", "gridvolume \"{}\": voxel ({}, {}, {}) channel {} has the invalid value {}", path,
                          voxel % data.nx, voxel / data.nx % data.ny, voxel / (size_t(data.nx) * data.ny),
                          i % data.channels, v);
        }
    }

    Transform to_world = props.get_transform("to_world");
    if (props.get_bool("use_grid_bbox", false)) {
        const Vec3f ext = data.bbox.extents();
        if (!data.bbox.valid() || !(ext.x > 0.f && ext.y > 0.f && ext.z > 0.f) || !all_finite(ext))
            props.fail_at("use_grid_bbox", "gridvolume \"{}\": the file has no usable bounding box", path);
        // The grid's unit cube is first mapped onto the file's bbox, then by to_world.
        to_world = to_world * Transform::translate(data.bbox.lo) * Transform::scale(ext);
    }
    return std::make_shared<Volume>(VoxelGrid(data, filter, wrap), to_world);
}

}  // namespace volguide
