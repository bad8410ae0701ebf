#include "volguide/integrators/guided/prepass/guided_prepass.h"

#include <bit>
#include <cmath>

#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/estimates/allocation.h"

namespace volguide {

namespace {

void put_u64(std::string& s, uint64_t v) {
    for (int i = 0; i < 8; ++i) s.push_back(char(uint8_t(v >> (8 * i))));
}
void put_u32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(char(uint8_t(v >> (8 * i))));
}

struct PrepassReader {
    const std::string& bytes;
    size_t pos = 0;
    uint64_t uint(int n, const char* what) {
        if (bytes.size() - pos < size_t(n))
            throw FieldFormatError(std::string("truncated guided_volpath pre-pass (in ") + what + ")");
        uint64_t v = 0;
        for (int i = 0; i < n; ++i) v |= uint64_t(uint8_t(bytes[pos + i])) << (8 * i);
        pos += size_t(n);
        return v;
    }
};

}  // namespace

std::string serialize_guided_prepass(const GuidingField& field, const Image& pixel_estimate,
                                     const std::string& allocation) {
    const std::string field_bytes = serialize_field(field);
    std::string s;
    put_u64(s, field_bytes.size());
    s += field_bytes;
    put_u32(s, uint32_t(pixel_estimate.width));
    put_u32(s, uint32_t(pixel_estimate.height));
    for (const Color3& c : pixel_estimate.pixels)
        for (int k = 0; k < 3; ++k) put_u32(s, std::bit_cast<uint32_t>(c[k]));
    if (!allocation.empty()) {
        put_u64(s, allocation.size());
        s += allocation;
    }
    return s;
}

GuidedPrepass deserialize_guided_prepass(const std::string& bytes) {
    PrepassReader r{bytes};
    const uint64_t field_size = r.uint(8, "field size");
    if (bytes.size() - r.pos < field_size) throw FieldFormatError("truncated guided_volpath pre-pass (in the field)");
    GuidedPrepass prepass;
    prepass.field = deserialize_field(bytes.substr(r.pos, field_size));
    r.pos += field_size;
    const uint64_t w = r.uint(4, "pixel estimate size"), h = r.uint(4, "pixel estimate size");
    if ((w == 0) != (h == 0) || w > 65536 || h > 65536 || (bytes.size() - r.pos) < w * h * 12)
        throw FieldFormatError("guided_volpath pre-pass: the pixel estimate's size does not match its data");
    if (w > 0) {
        prepass.pixel_estimate = Image(int(w), int(h));
        for (Color3& c : prepass.pixel_estimate.pixels)
            for (int k = 0; k < 3; ++k) {
                c[k] = std::bit_cast<float>(uint32_t(r.uint(4, "pixel estimate")));
                if (!std::isfinite(c[k])) throw FieldFormatError("guided_volpath pre-pass: a non-finite pixel estimate");
            }
    }
    if (r.pos == bytes.size()) return prepass;
    const uint64_t n = r.uint(8, "allocation size");
    if (bytes.size() - r.pos != n)
        throw FieldFormatError("guided_volpath pre-pass: the allocation's size does not match its data (a pre-pass of "
                               "an earlier volguide: train again)");
    prepass.allocation = bytes.substr(r.pos);
    try {  // checked here, used by the integrator
        (void)Allocation::deserialize(prepass.allocation);
    } catch (const std::runtime_error& e) {
        throw FieldFormatError(std::string("guided_volpath pre-pass: ") + e.what() + " (train again)");
    }
    return prepass;
}

}  // namespace volguide
