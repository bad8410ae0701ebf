// OpenVDB grids for `gridvolume` (volguide's extension to Mitsuba 3). This is the only file that
// includes OpenVDB's headers. One named grid (FloatGrid -> 1 channel, Vec3SGrid -> 3 channels) is
// densified over its active voxel bounding box; inactive voxels read as the grid's background.
// VDB voxel centres sit at integer index coordinates, so the dense grid's cells span index
// [min - 0.5, max + 0.5], and GridData::bbox is that box through the grid's transform: with
// use_grid_bbox the volume sits where the VDB file puts it. GridData is axis aligned, so only
// scale + translation transforms are accepted (negative scales flip the dense data).
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "volguide/core/error.h"
#include "volguide/core/memory.h"
#include "volguide/media/grid_data.h"
#include "volguide/media/vdb_header_check.h"

namespace volguide {

namespace {

[[noreturn]] void vdb_fail(const std::string& path, const std::string& what) {
    throw InputError(SourceLocation{path, 0}, fmt::format("\"{}\": {}", path, what));
}

void initialize_openvdb_once() {
    static std::once_flag flag;
    std::call_once(flag, [] { openvdb::initialize(); });
}

// Linear part and translation of an index-to-world map that must be an axis-aligned scale plus
// translation (row-vector convention: world = index * M, translation in row 3).
struct AxisMap {
    std::array<double, 3> scale{}, offset{};
};

AxisMap axis_aligned_map(const std::string& path, const std::string& grid_name,
                         const openvdb::math::Transform& xf) {
    if (!xf.isLinear())
        vdb_fail(path, fmt::format("grid \"{}\" has a non-linear ({}) transform; only axis-aligned scale and "
                                   "translation are supported",
                                   grid_name, xf.mapType()));
    // The matrix from where the map sends the origin and the unit vectors: getAffineMap() builds an
    // AffineMap, which throws from where it cannot be caught (std::terminate) for nearly singular
    // scales such as (1e-6, 1e-6, 1e-6) (found by fuzz_vdb).
    const openvdb::math::MapBase& map = *xf.baseMap();
    const openvdb::Vec3d t = map.applyMap(openvdb::Vec3d(0.0));
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int i = 0; i < 3; ++i) {
        openvdb::Vec3d e(0.0);
        e[i] = 1.0;
        const openvdb::Vec3d row = map.applyMap(e) - t;
        for (int j = 0; j < 3; ++j) m(i, j) = row[j];
        m(3, i) = t[i];
    }
    AxisMap a;
    double largest = 0.0;
    for (int i = 0; i < 3; ++i) largest = std::max(largest, std::abs(m(i, i)));
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (i != j && !(std::abs(m(i, j)) <= 1e-9 * largest))
                vdb_fail(path,
                         fmt::format("grid \"{}\" has a rotated or sheared transform; only axis-aligned "
                                     "scale and translation are supported",
                                     grid_name));
        }
        a.scale[i] = m(i, i);
        a.offset[i] = m(3, i);
        if (!(std::abs(a.scale[i]) > 0.0) || !std::isfinite(a.scale[i]) || !std::isfinite(a.offset[i]))
            vdb_fail(path, fmt::format("grid \"{}\" has a degenerate transform (scale {} along axis {})",
                                       grid_name, a.scale[i], i));
    }
    return a;
}

// The active voxel bounding box's size, checked against the dense grid's limits and the memory budget.
template <typename GridT>
std::array<int64_t, 3> dense_dimensions(const std::string& path, const GridT& grid,
                                        const openvdb::CoordBBox& box, int channels) {
    if (grid.activeVoxelCount() == 0 || box.empty())
        vdb_fail(path, fmt::format("grid \"{}\" is empty (it has no active voxels)", grid.getName()));
    const openvdb::Coord lo = box.min(), hi = box.max();
    std::array<int64_t, 3> dim;
    for (int i = 0; i < 3; ++i) dim[i] = int64_t(hi[i]) - int64_t(lo[i]) + 1;
    const uint64_t count = uint64_t(dim[0]) * uint64_t(dim[1]) * uint64_t(dim[2]) * uint64_t(channels);
    const uint64_t max_values = uint64_t(1) << 31;
    if (dim[0] > INT_MAX || dim[1] > INT_MAX || dim[2] > INT_MAX || count > max_values)
        vdb_fail(path, fmt::format("grid \"{}\" is too large to densify ({}x{}x{} active voxel bounding box)",
                                   grid.getName(), dim[0], dim[1], dim[2]));

    // A sparse grid's active box can be far larger than the file (background fills it), so the
    // dense copy is bounded by the machine's memory instead of the file's size.
    const uint64_t have = memory_budget_bytes();
    if (have > 0 && count * sizeof(float) > have)
        vdb_fail(path, fmt::format("grid \"{}\" densifies to {}x{}x{} voxels ({}), more than {}",
                                   grid.getName(), dim[0], dim[1], dim[2],
                                   format_bytes(count * sizeof(float)), memory_budget_description()));
    return dim;
}

// Cell extent in world space of the index box [lo - 0.5, hi + 0.5]; a negative scale reverses the
// axis, so the dense data is flipped along it.
BBox3f dense_world_box(const openvdb::CoordBBox& box, const AxisMap& map, std::array<bool, 3>& flip) {
    const openvdb::Coord lo = box.min(), hi = box.max();
    float world_lo[3], world_hi[3];
    for (int i = 0; i < 3; ++i) {
        const double a = (double(lo[i]) - 0.5) * map.scale[i] + map.offset[i];
        const double b = (double(hi[i]) + 0.5) * map.scale[i] + map.offset[i];
        flip[i] = map.scale[i] < 0.0;
        world_lo[i] = float(std::min(a, b));
        world_hi[i] = float(std::max(a, b));
    }
    return BBox3f(Point3f(world_lo[0], world_lo[1], world_lo[2]),
                  Point3f(world_hi[0], world_hi[1], world_hi[2]));
}

// Writes a grid's values into GridData::values: the background everywhere, then the active voxels
// and tiles. Runs of one value (the whole array, a tile's rows) are written as one voxel and then
// doubled with memcpy: per-voxel work beyond that is O(active voxels). Fuzz findings: probing every
// dense voxel, then even a plain loop filling a grid near the memory budget, took > 10 s under the
// fuzzer's instrumentation (ASan, coverage counters per iteration); memcpy is one call per run there too.
template <typename ValueT>
class DenseWriter {
  public:
    DenseWriter(GridData& g, const openvdb::Coord& lo, const std::array<bool, 3>& flip)
        : g_(g), lo_(lo), flip_(flip), channels_(size_t(g.channels)) {}

    void fill(const ValueT& background) {
        set_voxel(g_.values.data(), background);
        repeat_voxel(g_.values.data(), size_t(g_.nx) * size_t(g_.ny) * size_t(g_.nz));
    }

    void voxel(const openvdb::Coord& c, const ValueT& v) {
        set_voxel(
            &g_.values[index(int64_t(c.x()) - lo_.x(), int64_t(c.y()) - lo_.y(), int64_t(c.z()) - lo_.z())],
            v);
    }

    // One row of the tile along x (contiguous, reversed when x is flipped), then the others.
    void tile(const openvdb::CoordBBox& tile, const ValueT& v) {
        const int64_t x0 = int64_t(tile.min().x()) - lo_.x(), x1 = int64_t(tile.max().x()) - lo_.x();
        const size_t row = size_t(x1 - x0 + 1);
        auto row_start = [&](int64_t y, int64_t z) { return index(flip_[0] ? x1 : x0, y, z); };
        const int64_t y0 = int64_t(tile.min().y()) - lo_.y(), z0 = int64_t(tile.min().z()) - lo_.z();
        float* first = &g_.values[row_start(y0, z0)];
        set_voxel(first, v);
        repeat_voxel(first, row);
        for (int64_t z = z0; z <= int64_t(tile.max().z()) - lo_.z(); ++z)
            for (int64_t y = y0; y <= int64_t(tile.max().y()) - lo_.y(); ++y)
                if (y != y0 || z != z0)
                    std::memcpy(&g_.values[row_start(y, z)], first, row * channels_ * sizeof(float));
    }

  private:
    static void set_voxel(float* out, const ValueT& v) {
        if constexpr (std::is_same_v<ValueT, float>) {
            out[0] = v;
        } else {
            for (int c = 0; c < 3; ++c) out[c] = float(v[c]);
        }
    }
    // out[0, channels) holds a voxel; copies it to fill out[0, voxels * channels).
    void repeat_voxel(float* out, size_t voxels) const {
        const size_t total = voxels * channels_;
        for (size_t done = channels_; done < total;) {
            const size_t n = std::min(done, total - done);
            std::memcpy(out + done, out, n * sizeof(float));
            done += n;
        }
    }
    size_t index(int64_t x, int64_t y, int64_t z) const {  // x, y, z relative to lo
        const int64_t ix = flip_[0] ? g_.nx - 1 - x : x, iy = flip_[1] ? g_.ny - 1 - y : y,
                      iz = flip_[2] ? g_.nz - 1 - z : z;
        return ((size_t(iz) * size_t(g_.ny) + size_t(iy)) * size_t(g_.nx) + size_t(ix)) * channels_;
    }

    GridData& g_;
    const openvdb::Coord lo_;
    const std::array<bool, 3> flip_;
    const size_t channels_;
};

template <typename GridT>
GridData densify(const std::string& path, const GridT& grid, int channels) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    const std::array<int64_t, 3> dim = dense_dimensions(path, grid, box, channels);
    const AxisMap map = axis_aligned_map(path, grid.getName(), grid.transform());
    GridData g;
    g.nx = int(dim[0]);
    g.ny = int(dim[1]);
    g.nz = int(dim[2]);
    g.channels = channels;
    g.values.resize(uint64_t(dim[0]) * uint64_t(dim[1]) * uint64_t(dim[2]) * uint64_t(channels));
    std::array<bool, 3> flip;
    g.bbox = dense_world_box(box, map, flip);

    DenseWriter<typename GridT::ValueType> writer(g, box.min(), flip);
    writer.fill(grid.background());
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        if (it.isVoxelValue()) {
            writer.voxel(it.getCoord(), *it);
            continue;
        }
        openvdb::CoordBBox tile;
        it.getBoundingBox(tile);
        tile.intersect(box);  // inside the active box by construction; clipped all the same
        if (!tile.empty()) writer.tile(tile, *it);
    }
    return g;
}

}  // namespace

GridData read_vdb_file(const std::string& path, const std::string& grid_name) {
    initialize_openvdb_once();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) vdb_fail(path, "cannot open the .vdb file (no such file)");
    if (std::filesystem::is_directory(path, ec))
        vdb_fail(path, "cannot open the .vdb file (it is a directory)");

    check_vdb_header(path);

    openvdb::GridBase::Ptr base;
    std::vector<std::string> names;
    std::string unsupported_type;
    try {
        openvdb::io::File file(path);
        file.open(/*delayLoad=*/false);
        for (auto it = file.beginName(); it != file.endName(); ++it) names.push_back(it.gridName());
        if (file.hasGrid(grid_name)) {
            // The type first (metadata and transform only): the header check bounds the trees of the
            // types read here, not point grids' (vdb_header_check.h).
            const openvdb::GridBase::Ptr meta = file.readGridMetadata(grid_name);
            if (!meta->isType<openvdb::FloatGrid>() && !meta->isType<openvdb::Vec3SGrid>())
                unsupported_type = fmt::format("{} (value type {})", meta->type(), meta->valueType());
            else
                base = file.readGrid(grid_name);
        }
        file.close();
    } catch (const openvdb::Exception& e) {
        vdb_fail(path, fmt::format("cannot read the .vdb file: {}", e.what()));
    } catch (const std::exception& e) {
        vdb_fail(path, fmt::format("cannot read the .vdb file: {}", e.what()));
    }
    if (!unsupported_type.empty())
        vdb_fail(path, fmt::format("grid \"{}\" has the unsupported type {}; only float (FloatGrid) and vec3s "
                                   "(Vec3SGrid) grids are supported",
                                   grid_name, unsupported_type));
    if (!base) {
        std::string list;
        for (const std::string& n : names) list += (list.empty() ? "\"" : ", \"") + n + "\"";
        vdb_fail(path, names.empty()
                           ? fmt::format("no grid \"{}\" (the file has no grids)", grid_name)
                           : fmt::format("no grid \"{}\" (the file has grids {})", grid_name, list));
    }
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(base)) return densify(path, *f, 1);
    if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base)) return densify(path, *v, 3);
    vdb_fail(path, fmt::format("grid \"{}\" has the unsupported type {} (value type {}); only float "
                               "(FloatGrid) and vec3s (Vec3SGrid) grids are supported",
                               grid_name, base->type(), base->valueType()));
}

}  // namespace volguide
