#pragma once
// Little-endian bytes of the project's binary records (statistics, allocations, pre-pass parts): a
// writer that appends and a reader that checks every read against what is left, throwing
// std::runtime_error naming the record and the field that was cut short. Floats keep their bits.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace volguide {

class ByteWriter {
  public:
    void u32(uint32_t v) { put(v, 4); }
    void u64(uint64_t v) { put(v, 8); }
    void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
    // A length-prefixed byte string.
    void bytes(const std::string& b) {
        u64(b.size());
        out_ += b;
    }
    const std::string& str() const { return out_; }
    std::string take() { return std::move(out_); }

  private:
    void put(uint64_t v, int n) {
        for (int i = 0; i < n; ++i) out_.push_back(char(uint8_t(v >> (8 * i))));
    }
    std::string out_;
};

class ByteReader {
  public:
    // `record`: what the bytes are, for the errors ("cell statistics").
    ByteReader(const std::string& bytes, const char* record) : bytes_(bytes), record_(record) {}
    uint32_t u32(const char* field) { return uint32_t(get(4, field)); }
    uint64_t u64(const char* field) { return get(8, field); }
    float f32(const char* field) { return std::bit_cast<float>(u32(field)); }
    double f64(const char* field) { return std::bit_cast<double>(u64(field)); }
    std::string bytes(const char* field) {
        const uint64_t n = u64(field);
        if (left() < n) fail("truncated", field);
        std::string b = bytes_.substr(pos_, size_t(n));
        pos_ += size_t(n);
        return b;
    }
    size_t left() const { return bytes_.size() - pos_; }
    // Throws unless every byte was read.
    void finish() const {
        if (left() != 0) fail("trailing bytes after", "the last field");
    }
    [[noreturn]] void fail(const char* what, const char* field) const {
        throw std::runtime_error(std::string(record_) + ": " + what + " " + field);
    }

  private:
    uint64_t get(int n, const char* field) {
        if (left() < size_t(n)) fail("truncated in", field);
        uint64_t v = 0;
        for (int i = 0; i < n; ++i) v |= uint64_t(uint8_t(bytes_[pos_ + size_t(i)])) << (8 * i);
        pos_ += size_t(n);
        return v;
    }
    const std::string& bytes_;
    const char* record_;
    size_t pos_ = 0;
};

}  // namespace volguide
