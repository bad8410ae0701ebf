#include "volguide/render/exr_header_check.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <climits>

#include "volguide/core/error.h"
#include "volguide/core/memory.h"

namespace volguide {

namespace {

[[noreturn]] void header_fail(const std::string& path, const std::string& what) {
    throw InputError(SourceLocation{path, 0}, "invalid EXR header: " + what);
}

// EXR layout: magic (4 bytes), version and flags (4), then per part a list of attributes
// name\0 type\0 int32 size, size bytes; an empty name ends a part's header, and multi-part files
// end the list of headers with one more empty header.
constexpr uint32_t kMultiPartFlag = 0x1000;
constexpr uint32_t kLongNamesFlag = 0x400;

// Reads the header from the start of the file as it goes: images are large and their headers
// small, so only the bytes the walk needs are read; sizes are checked against the file's size.
class HeaderWalker {
  public:
    HeaderWalker(const std::string& path, std::ifstream& in, uint64_t file_size, size_t max_name)
        : path_(path), in_(in), file_size_(file_size), max_name_(max_name) {}

    // Returns the number of attributes of the header starting at the current position.
    size_t walk_header() {
        size_t attributes = 0;
        while (true) {
            const std::string name = read_name("attribute name");
            if (name.empty()) return attributes;
            read_name("attribute type of \"" + name + "\"");
            const int32_t size = read_int("size of attribute \"" + name + "\"");
            if (size < 0 || uint64_t(size) > file_size_ - pos_)
                header_fail(path_, fmt::format("attribute \"{}\" declares {} bytes but the file has {} left", name,
                                               size, file_size_ - pos_));
            pos_ += uint64_t(size);
            ++attributes;
        }
    }
    bool at_empty_header() { return pos_ < file_size_ && byte_at(pos_) == '\0'; }

  private:
    char byte_at(uint64_t offset) {
        char c = 0;
        in_.seekg(std::streamoff(offset));
        if (!in_.get(c)) header_fail(path_, "read error");
        return c;
    }
    std::string read_name(const std::string& what) {
        std::string s;
        while (true) {
            if (pos_ >= file_size_) header_fail(path_, what + " runs past the end of the file");
            const char c = byte_at(pos_++);
            if (c == '\0') return s;
            if (s.size() == max_name_)
                header_fail(path_, fmt::format("{} is longer than {} characters", what, max_name_));
            s += c;
        }
    }
    int32_t read_int(const std::string& what) {
        if (file_size_ - pos_ < 4) header_fail(path_, what + " runs past the end of the file");
        char b[4];
        in_.seekg(std::streamoff(pos_));
        if (!in_.read(b, 4)) header_fail(path_, "read error");
        int32_t v;
        std::memcpy(&v, b, 4);  // little endian, as the file and the host
        pos_ += 4;
        return v;
    }

    const std::string& path_;
    std::ifstream& in_;
    uint64_t file_size_;
    size_t max_name_;
    uint64_t pos_ = 8;
};

}  // namespace

void check_exr_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(SourceLocation{path, 0}, "cannot open image file");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0);
    char start[8];
    if (size < 8 || !in.read(start, 8) || std::memcmp(start, "\x76\x2f\x31\x01", 4) != 0)
        throw InputError(SourceLocation{path, 0}, "not an EXR file (no EXR magic number)");
    uint32_t version;
    std::memcpy(&version, start + 4, 4);
    HeaderWalker walker(path, in, uint64_t(size), (version & kLongNamesFlag) ? 255 : 31);
    if (!(version & kMultiPartFlag)) {
        walker.walk_header();
        return;
    }
    // Multi-part: headers until an empty one.
    while (!walker.at_empty_header()) {
        if (walker.walk_header() == 0) header_fail(path, "a part's header has no attributes");
    }
}

ExrSize checked_exr_size(const std::string& path, int min_x, int min_y, int max_x, int max_y, size_t channels) {
    // In 64 bits: a window from INT_MIN to INT_MAX overflows int.
    const int64_t width = int64_t(max_x) - min_x + 1, height = int64_t(max_y) - min_y + 1;
    if (width < 1 || height < 1 || width > INT_MAX || height > INT_MAX)
        throw InputError(SourceLocation{path, 0},
                         fmt::format("invalid EXR data window ({} x {} pixels)", width, height));
    const uint64_t bytes = uint64_t(width) * uint64_t(height) * sizeof(float) * std::max<uint64_t>(channels, 1);
    const uint64_t have = physical_memory_bytes();
    if (have > 0 && bytes > have)
        throw InputError(SourceLocation{path, 0},
                         fmt::format("a {} x {} EXR with {} channels needs {}, more than this machine's {}", width,
                                     height, channels, format_bytes(bytes), format_bytes(have)));
    return {int(width), int(height)};
}

}  // namespace volguide
