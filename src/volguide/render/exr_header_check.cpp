#include "volguide/render/exr_header_check.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <optional>

#include "volguide/core/error.h"
#include "volguide/core/memory.h"

namespace volguide {

namespace {

[[noreturn]] void header_fail(const std::string& path, const std::string& what) {
    throw InputError(SourceLocation{path, 0}, "invalid EXR header: " + what);
}

// The product, or UINT64_MAX where it would wrap.
uint64_t saturating_product(std::initializer_list<uint64_t> factors) {
    uint64_t product = 1;
    for (uint64_t f : factors) {
        if (f != 0 && product > UINT64_MAX / f) return UINT64_MAX;
        product *= f;
    }
    return product;
}

constexpr uint64_t kMaxCompressionRatio = 1100;

// Why `channels` float channels of width x height pixels (`what`, e.g. "a 4 x 3 EXR") cannot be
// decoded from a file of `file_size` bytes (unknown: not checked), or "" when they can. No EXR
// compression packs more than deflate's limit of about 1032:1 (ZIP; RLE, PIZ and B44 pack less),
// and half channels double when read as float: a file smaller than that cannot hold them, whatever
// its header says, and reading it would only allocate for the failure. They must also fit the
// memory budget. The product saturates: 2^30 x 2^30 pixels of 4 channels wrap 64 bits.
std::string decode_size_problem(const std::string& what, uint64_t width, uint64_t height, size_t channels,
                                std::optional<uint64_t> file_size) {
    const uint64_t bytes = saturating_product({width, height, sizeof(float), channels});
    if (file_size && bytes > 2 * kMaxCompressionRatio * *file_size + (uint64_t(1) << 20))
        return fmt::format("{} with {} channels cannot fit in {} bytes, even compressed", what, channels,
                           *file_size);
    const uint64_t have = memory_budget_bytes();
    if (have > 0 && bytes > have)
        return fmt::format("{} with {} channels needs {}, more than {}", what, channels, format_bytes(bytes),
                           memory_budget_description());
    return {};
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
        part_ = PartLayout{};
        while (true) {
            const std::string name = read_name("attribute name");
            if (name.empty()) {
                check_decode_buffers();
                return attributes;
            }
            const std::string type = read_name("attribute type of \"" + name + "\"");
            const int32_t size = read_int("size of attribute \"" + name + "\"");
            if (size < 0 || uint64_t(size) > file_size_ - pos_)
                header_fail(path_, fmt::format("attribute \"{}\" declares {} bytes but the file has {} left",
                                               name, size, file_size_ - pos_));
            check_value(name, type, uint64_t(size));
            pos_ += uint64_t(size);
            ++attributes;
        }
    }
    bool at_empty_header() { return pos_ < file_size_ && byte_at(pos_) == '\0'; }

  private:
    // OpenEXR reads a value of a known type by its layout, not by the declared size: a size that
    // disagrees would make it read past the attribute, out of step with this walk, so each type's
    // layout must match its size exactly. Unknown types are skipped by size, as OpenEXR does.
    void check_value(const std::string& name, const std::string& type, uint64_t size) {
        static const std::pair<const char*, uint64_t> fixed[] = {
            {"box2i", 16},   {"box2f", 16},         {"v2i", 8},         {"v2f", 8},
            {"v2d", 16},     {"v3i", 12},           {"v3f", 12},        {"v3d", 24},
            {"m33f", 36},    {"m33d", 72},          {"m44f", 64},       {"m44d", 128},
            {"int", 4},      {"float", 4},          {"double", 8},      {"rational", 8},
            {"timecode", 8}, {"keycode", 28},       {"compression", 1}, {"lineOrder", 1},
            {"envmap", 1},   {"deepImageState", 1}, {"tiledesc", 9},    {"chromaticities", 32}};
        for (const auto& [t, n] : fixed)
            if (type == t && size != n)
                header_fail(path_, fmt::format("attribute \"{}\" of type {} has {} bytes, expected {}", name,
                                               type, size, n));
        if (type == "chlist") part_.channels = check_channel_list(name, size);
        if (type == "stringvector") check_string_vector(name, size);
        if (type == "preview") check_preview(name, size);
        if (name == "dataWindow" && type == "box2i") {
            part_.has_window = true;
            for (int i = 0; i < 4; ++i) part_.window[i] = int_at(pos_ + 4 * uint64_t(i));
        }
        if (name == "compression" && type == "compression") part_.compression = uint8_t(byte_at(pos_));
        if (name == "tiles" && type == "tiledesc") {
            part_.tiled = true;
            part_.tile_x = uint32_t(int_at(pos_));
            part_.tile_y = uint32_t(int_at(pos_ + 4));
        }
    }
    // What OpenEXR allocates when it opens a part, before reading a pixel: buffers of whole
    // blocks of scanlines (up to 256 lines for DWAB, whatever the image's height) or of whole tiles.
    // A header declaring a 2-million-pixel-wide strip made it allocate and free hundreds of MB for a
    // 417-byte file (the fuzzer's image target, docs/reliability.md), so these buffers are bounded
    // like the image (checked_exr_size) before OpenEXR sees the file.
    void check_decode_buffers() {
        if (!part_.has_window) return;
        const int64_t width = int64_t(part_.window[2]) - part_.window[0] + 1;
        const int64_t height = int64_t(part_.window[3]) - part_.window[1] + 1;
        if (width < 1 || height < 1 || width > INT_MAX || height > INT_MAX)
            header_fail(path_, fmt::format("invalid EXR data window ({} x {} pixels)", width, height));
        const size_t channels = std::max<size_t>(part_.channels, 1);
        // The whole image is bounded later, against the channels read (checked_exr_size).
        const int64_t lines = lines_per_block(part_.compression);
        check_buffer(uint64_t(width), uint64_t(lines), channels,
                     fmt::format("a {} x {} block of scanlines", width, lines));
        if (part_.tiled)
            check_buffer(part_.tile_x, part_.tile_y, channels,
                         fmt::format("a tile of {} x {} pixels", part_.tile_x, part_.tile_y));
    }
    void check_buffer(uint64_t width, uint64_t height, size_t channels, const std::string& what) {
        const std::string problem = decode_size_problem(what, width, height, channels, file_size_);
        if (!problem.empty()) header_fail(path_, problem);
    }
    // Scanlines per compressed block, by EXR's compression codes (none, RLE, ZIPS, ZIP, PIZ, PXR24,
    // B44, B44A, DWAA, DWAB).
    static int64_t lines_per_block(uint8_t compression) {
        static const int64_t lines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
        return compression < std::size(lines) ? lines[compression] : 256;
    }
    // Channels: name\0 and 16 bytes each, then an empty name, exactly filling the attribute.
    // Returns the number of channels.
    size_t check_channel_list(const std::string& name, uint64_t size) {
        const uint64_t end = pos_ + size;
        uint64_t p = pos_;
        size_t count = 0;
        while (true) {
            if (p >= end) header_fail(path_, fmt::format("channel list \"{}\" is not terminated", name));
            size_t len = 0;
            while (p < end && byte_at(p) != '\0') ++p, ++len;
            if (p >= end) header_fail(path_, fmt::format("channel list \"{}\" is not terminated", name));
            ++p;
            if (len == 0) break;
            if (len > max_name_ || end - p < 16)
                header_fail(path_, fmt::format("channel list \"{}\" has a malformed channel", name));
            p += 16;
            ++count;
        }
        if (p != end)
            header_fail(path_, fmt::format("channel list \"{}\" does not fill its {} bytes", name, size));
        return count;
    }
    // Strings, each an int32 length and its bytes, exactly filling the attribute.
    void check_string_vector(const std::string& name, uint64_t size) {
        const uint64_t end = pos_ + size;
        uint64_t p = pos_;
        while (p < end) {
            if (end - p < 4) header_fail(path_, fmt::format("string vector \"{}\" is truncated", name));
            const int32_t len = int_at(p);
            p += 4;
            if (len < 0 || uint64_t(len) > end - p)
                header_fail(path_, fmt::format("string vector \"{}\" has a string of {} bytes in {} left",
                                               name, len, end - p));
            p += uint64_t(len);
        }
    }
    // A preview image: uint32 width and height, then 4 bytes a pixel, exactly.
    void check_preview(const std::string& name, uint64_t size) {
        if (size < 8) header_fail(path_, fmt::format("preview \"{}\" is truncated", name));
        const uint64_t w = uint32_t(int_at(pos_)), h = uint32_t(int_at(pos_ + 4));
        if (8 + 4 * w * h != size)
            header_fail(path_,
                        fmt::format("preview \"{}\" of {} x {} pixels has {} bytes", name, w, h, size));
    }
    int32_t int_at(uint64_t offset) {
        char b[4];
        in_.seekg(std::streamoff(offset));
        if (!in_.read(b, 4)) header_fail(path_, "read error");
        int32_t v;
        std::memcpy(&v, b, 4);
        return v;
    }

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
    // The attributes of the part being walked that size OpenEXR's buffers.
    struct PartLayout {
        bool has_window = false;
        int32_t window[4] = {};  // min x, min y, max x, max y
        uint8_t compression = 0;
        size_t channels = 0;
        bool tiled = false;
        uint32_t tile_x = 0, tile_y = 0;
    } part_;
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

ExrSize checked_exr_size(const std::string& path, int min_x, int min_y, int max_x, int max_y,
                         size_t channels) {
    // In 64 bits: a window from INT_MIN to INT_MAX overflows int.
    const int64_t width = int64_t(max_x) - min_x + 1, height = int64_t(max_y) - min_y + 1;
    if (width < 1 || height < 1 || width > INT_MAX || height > INT_MAX)
        throw InputError(SourceLocation{path, 0},
                         fmt::format("invalid EXR data window ({} x {} pixels)", width, height));
    std::error_code ec;
    const uint64_t file_size = std::filesystem::file_size(path, ec);
    const std::string problem = decode_size_problem(
        fmt::format("a {} x {} EXR", width, height), uint64_t(width), uint64_t(height),
        std::max<size_t>(channels, 1), ec ? std::nullopt : std::optional<uint64_t>(file_size));
    if (!problem.empty()) throw InputError(SourceLocation{path, 0}, problem);
    return {int(width), int(height)};
}

}  // namespace volguide
