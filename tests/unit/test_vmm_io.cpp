// Binary VMM serialization: bit-exact round trips; every truncation, every single-byte corruption,
// foreign data, a newer version, an over-capacity record and invalid values with a valid checksum
// all throw VmmFormatError (never crash, never return a mixture).
#include <gtest/gtest.h>

#include <bit>
#include <sstream>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/vmm_io.h"

using namespace volguide;

namespace {
Vmm sample_vmm(int lobes) {
    Vmm m;
    Sampler s(4, 0, 0);
    for (int k = 0; k < lobes; ++k)
        m.add_lobe(0.1f + s.next_1d(),
                   VmfLobe(warp::square_to_uniform_sphere(s.next_2d()), 100.f * s.next_1d()));
    m.normalize_weights();
    return m;
}

std::string serialize(const Vmm& m) {
    std::ostringstream out(std::ios::binary);
    write_vmm(out, m);
    return out.str();
}

template <int N = kVmmMaxLobes>
VmfMixture<N> deserialize(const std::string& bytes) {
    std::istringstream in(bytes, std::ios::binary);
    return read_vmm<N>(in);
}

// The format's checksum (FNV-1a over everything between the magic and the checksum).
void fix_checksum(std::string& bytes) {
    uint32_t h = 2166136261u;
    for (size_t i = 8; i + 4 < bytes.size(); ++i) h = (h ^ uint8_t(bytes[i])) * 16777619u;
    for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + i] = char(h >> (8 * i));
}
void put_float(std::string& bytes, size_t offset, float v) {
    uint32_t u = std::bit_cast<uint32_t>(v);
    for (int i = 0; i < 4; ++i) bytes[offset + i] = char(u >> (8 * i));
}
}  // namespace

TEST(VmmIo, RoundTripIsBitExact) {
    for (int lobes : {0, 1, 8, kVmmMaxLobes}) {
        Vmm m = sample_vmm(lobes);
        std::string bytes = serialize(m);
        EXPECT_EQ(bytes.size(), 8 + 8 + 20 * size_t(lobes) + 4);
        Vmm back = deserialize(bytes);
        ASSERT_EQ(back.size(), m.size());
        for (int k = 0; k < m.size(); ++k) {
            EXPECT_EQ(back.weight[k], m.weight[k]);
            EXPECT_EQ(back.mu_x[k], m.mu_x[k]);
            EXPECT_EQ(back.mu_y[k], m.mu_y[k]);
            EXPECT_EQ(back.mu_z[k], m.mu_z[k]);
            EXPECT_EQ(back.kappa[k], m.kappa[k]);
            EXPECT_EQ(back.norm[k], m.norm[k]);
        }
    }
}

TEST(VmmIo, SeveralRecordsInOneStream) {
    std::ostringstream out(std::ios::binary);
    write_vmm(out, sample_vmm(3));
    write_vmm(out, sample_vmm(5));
    std::istringstream in(out.str(), std::ios::binary);
    EXPECT_EQ(read_vmm<kVmmMaxLobes>(in).size(), 3);
    EXPECT_EQ(read_vmm<kVmmMaxLobes>(in).size(), 5);
    EXPECT_THROW(read_vmm<kVmmMaxLobes>(in), VmmFormatError);  // end of stream
}

TEST(VmmIo, EveryTruncationThrows) {
    std::string bytes = serialize(sample_vmm(4));
    for (size_t n = 0; n < bytes.size(); ++n)
        EXPECT_THROW(deserialize(bytes.substr(0, n)), VmmFormatError) << n;
}

TEST(VmmIo, EverySingleByteCorruptionThrows) {
    std::string bytes = serialize(sample_vmm(4));
    for (size_t i = 0; i < bytes.size(); ++i)
        for (uint8_t flip : {0x01, 0x80, 0xff}) {
            std::string bad = bytes;
            bad[i] = char(uint8_t(bad[i]) ^ flip);
            EXPECT_THROW(deserialize(bad), VmmFormatError) << "byte " << i;
        }
}

TEST(VmmIo, ForeignDataThrows) {
    EXPECT_THROW(deserialize(""), VmmFormatError);
    EXPECT_THROW(deserialize("<scene version=\"3.0.0\">"), VmmFormatError);
    std::string noise(200, '\0');
    Sampler s(1, 0, 0);
    for (char& c : noise) c = char(int(s.next_1d() * 256));
    EXPECT_THROW(deserialize(noise), VmmFormatError);
}

TEST(VmmIo, NewerVersionAndOverCapacityThrow) {
    std::string bytes = serialize(sample_vmm(8));
    EXPECT_THROW(deserialize<4>(bytes), VmmFormatError);
    EXPECT_NO_THROW(deserialize<8>(bytes));
    std::string v2 = bytes;
    v2[8] = 2;
    fix_checksum(v2);
    try {
        deserialize(v2);
        FAIL() << "version 2 accepted";
    } catch (const VmmFormatError& e) {
        EXPECT_NE(std::string(e.what()).find("version"), std::string::npos) << e.what();
    }
    std::string huge = bytes;
    huge[12] = char(0xff), huge[13] = char(0xff), huge[14] = char(0xff), huge[15] = char(0x7f);
    fix_checksum(huge);
    EXPECT_THROW(deserialize(huge), VmmFormatError);
}

TEST(VmmIo, InvalidValuesWithValidChecksumThrow) {
    const std::string bytes = serialize(sample_vmm(2));
    const size_t lobe0 = 16;  // weight, mu.x, mu.y, mu.z, kappa
    struct Edit {
        size_t offset;
        float value;
    };
    for (Edit e : {Edit{lobe0, std::nanf("")}, Edit{lobe0, -0.5f}, Edit{lobe0, 0.9f}, Edit{lobe0 + 4, 2.f},
                   Edit{lobe0 + 16, -1.f}, Edit{lobe0 + 16, std::numeric_limits<float>::infinity()},
                   Edit{lobe0 + 16, 1e9f}}) {
        std::string bad = bytes;
        put_float(bad, e.offset, e.value);
        fix_checksum(bad);
        EXPECT_THROW(deserialize(bad), VmmFormatError) << e.offset << " " << e.value;
    }
    // Writing refuses what reading would reject.
    Vmm unnormalised = sample_vmm(3);
    unnormalised.weight[0] += 0.5f;
    std::ostringstream out;
    EXPECT_THROW(write_vmm(out, unnormalised), VmmFormatError);
}
