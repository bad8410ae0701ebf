#include "volguide/media/vdb_header_check.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "volguide/core/error.h"

namespace volguide {

namespace {

// Layout (little endian): int64 magic 0x56444220, uint32 file version, uint32 library major and minor,
// char has-grid-offsets, 36-char UUID, the file's metadata map, int32 grid count, then per grid a
// descriptor (name, type and instance-parent strings, int64 grid, block and end offsets) followed by
// the grid, the next descriptor starting at the end offset; at each grid offset: uint32
// compression, then the grid's metadata map. Strings are uint32 length + bytes;
// a metadata map is uint32 count, then per entry name and type strings and uint32 size + value.
constexpr uint32_t kMinFormat = 222;  // OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION

class VdbWalker {
  public:
    VdbWalker(const std::string& path, std::ifstream& in, uint64_t size) : path_(path), in_(in), size_(size) {}

    void walk() {
        if (size_ < 57 || u32_at(0) != 0x56444220 || u32_at(4) != 0)
            fail("not a .vdb file (no OpenVDB magic number)");
        const uint32_t version = u32_at(8);
        if (version < kMinFormat)
            fail(fmt::format("file format {} is older than the {} volguide reads", version, kMinFormat));
        if (byte_at(20) == 0) fail("a stream without grid offsets (volguide reads files written by io::File)");
        pos_ = 57;  // after magic, version, library version, the offsets flag and the UUID
        walk_metadata("the file's metadata");
        const int32_t grids = int32_t(read_u32("grid count"));
        // A descriptor is at least three empty strings and three offsets: 36 bytes.
        if (grids < 0 || uint64_t(grids) > (size_ - pos_) / 36)
            fail(fmt::format("{} grids declared in {} bytes", grids, size_ - pos_));
        std::vector<uint64_t> offsets;
        for (int32_t g = 0; g < grids; ++g) {
            skip_string("grid name");
            skip_string("grid type");
            skip_string("instance parent");
            const uint64_t grid = read_u64("grid offset"), block = read_u64("block offset"), end = read_u64("end offset");
            if (pos_ > grid || grid > block || block > end || end > size_)
                fail(fmt::format("grid {} has offsets {}, {}, {} outside the file's {} bytes", g, grid, block, end, size_));
            offsets.push_back(grid);
            pos_ = end;  // each descriptor is followed by its grid; the next descriptor starts after it
        }
        for (uint64_t grid : offsets) {
            pos_ = grid;
            read_u32("grid compression");
            walk_metadata("a grid's metadata");
        }
    }

  private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(SourceLocation{path_, 0}, fmt::format("\"{}\": cannot read the .vdb file: {}", path_, what));
    }
    void read_at(uint64_t offset, char* out, size_t n) {
        in_.seekg(std::streamoff(offset));
        if (!in_.read(out, std::streamsize(n))) fail("read error");
    }
    uint32_t u32_at(uint64_t offset) {
        char b[4];
        read_at(offset, b, 4);
        uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
    }
    char byte_at(uint64_t offset) {
        char c;
        read_at(offset, &c, 1);
        return c;
    }
    void need(uint64_t n, const std::string& what) {
        if (pos_ > size_ || n > size_ - pos_)
            fail(fmt::format("{} ({} bytes at offset {}) runs past the end of the file ({} bytes)", what, n, pos_, size_));
    }
    uint32_t read_u32(const std::string& what) {
        need(4, what);
        const uint32_t v = u32_at(pos_);
        pos_ += 4;
        return v;
    }
    uint64_t read_u64(const std::string& what) {
        need(8, what);
        char b[8];
        read_at(pos_, b, 8);
        uint64_t v;
        std::memcpy(&v, b, 8);
        pos_ += 8;
        return v;
    }
    void skip_string(const std::string& what) {
        const uint32_t n = read_u32("length of the " + what);
        need(n, "the " + what);
        pos_ += n;
    }
    void walk_metadata(const std::string& what) {
        const uint32_t count = read_u32("entry count of " + what);
        // An entry is at least two empty strings and an empty value: 12 bytes.
        if (pos_ > size_ || count > (size_ - pos_) / 12)
            fail(fmt::format("{} declares {} entries in {} bytes", what, count, size_ - std::min(pos_, size_)));
        for (uint32_t i = 0; i < count; ++i) {
            skip_string("metadata name");
            skip_string("metadata type");
            const uint32_t n = read_u32("metadata size");
            need(n, "a metadata value");
            pos_ += n;
        }
    }

    const std::string& path_;
    std::ifstream& in_;
    uint64_t size_;
    uint64_t pos_ = 0;
};

}  // namespace

void check_vdb_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(SourceLocation{path, 0}, fmt::format("\"{}\": cannot open the .vdb file", path));
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    VdbWalker(path, in, uint64_t(std::max<std::streamoff>(size, 0))).walk();
}

}  // namespace volguide
