// Save/load of the guiding field: the round trip is bit-exact and gives identical queries; corrupt,
// truncated, foreign, newer-version and inconsistent files are rejected with a clear error; the
// per-leaf medium fractions (format 3) round-trip and format 2 files still load, unmeasured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/field_io.h"

using namespace volguide;

namespace {

GuidingField make_field() {
    std::vector<RadianceSample> s;
    for (int i = 0; i < 12000; ++i) {
        Sampler r(9, 0, uint64_t(i));
        const Point3f p(r.next_1d(), r.next_1d(), 2.f * r.next_1d());
        // A tenth of the samples "direct" (a photon's first collision): the leaves fit both VMMs.
        s.push_back(
            {p, warp::square_to_uniform_sphere(r.next_2d()), Color3(1.f, 0.5f, 0.25f), 1.f, i % 10 == 0});
    }
    // Leaves hold 750..1500 samples; min_samples 1000 makes some of them invalid.
    GuidingFieldSettings settings;
    settings.tree.max_samples = 1500;
    settings.lobes = 3;
    settings.min_samples = 1000;
    return GuidingField::build(BBox3f(Point3f(0.f), Point3f(1.f, 1.f, 4.f)), s, settings);
}

void expect_rejected(const std::string& bytes, const std::string& needle) {
    try {
        deserialize_field(bytes);
        FAIL() << "accepted; expected an error containing \"" << needle << "\"";
    } catch (const FieldFormatError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(GuidingFieldIo, RoundTripIsExact) {
    const GuidingField field = make_field();
    bool has_invalid = false;
    for (const auto& l : field.leaves()) has_invalid |= !l.valid;
    ASSERT_TRUE(has_invalid);
    const std::string bytes = serialize_field(field);
    const GuidingField back = deserialize_field(bytes);
    EXPECT_EQ(serialize_field(back), bytes);
    int indirect = 0;
    for (size_t l = 0; l < field.leaves().size(); ++l) {
        const GuidingLeaf &a = field.leaves()[l], &b = back.leaves()[l];
        ASSERT_EQ(a.valid_indirect, b.valid_indirect);
        if (!a.valid_indirect) continue;
        ++indirect;
        const Vec3f w(0.f, 0.6f, 0.8f);
        EXPECT_EQ(a.vmm_indirect.pdf(w), b.vmm_indirect.pdf(w));
    }
    EXPECT_GT(indirect, 0);
    const PhaseVmm phase = hg_phase_vmm(0.6f);
    for (int i = 0; i < 500; ++i) {
        Sampler r(10, 0, uint64_t(i));
        const Point3f x(r.next_1d(), r.next_1d(), 4.f * r.next_1d());
        const Vec3f w = warp::square_to_uniform_sphere(r.next_2d());
        EXPECT_EQ(field.incident(x, w), back.incident(x, w));
        EXPECT_EQ(field.inscattered(x, w, phase), back.inscattered(x, w, phase));
    }
}

TEST(GuidingFieldIo, SaveAndLoadThroughAFile) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("volguide-field-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "f.vgfield").string();
    const GuidingField field = make_field();
    save_field(path, field);
    EXPECT_EQ(serialize_field(load_field(path)), serialize_field(field));
    try {
        load_field((dir / "missing.vgfield").string());
        FAIL();
    } catch (const FieldFormatError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.vgfield"), std::string::npos);
    }
    std::filesystem::remove_all(dir);
}

TEST(GuidingFieldIo, CorruptFilesAreRejected) {
    const std::string good = serialize_field(make_field());
    // 1. Foreign data.
    expect_rejected("P6\n10 10\n255\n" + std::string(100, 'x'), "magic");
    // 2. Truncated anywhere: the checksum (or the size checks) catch it.
    for (size_t cut : {size_t(3), size_t(20), good.size() / 2, good.size() - 1}) {
        EXPECT_THROW(deserialize_field(good.substr(0, cut)), FieldFormatError) << "cut at " << cut;
    }
    // 3. A flipped byte in the body.
    for (size_t at : {size_t(14), good.size() / 3, good.size() - 12}) {
        std::string bad = good;
        bad[at] = char(bad[at] ^ 0x5a);
        EXPECT_THROW(deserialize_field(bad), FieldFormatError) << "byte " << at;
    }
    // 4. A newer version.
    std::string newer = good;
    newer[8] = char(kFieldFormatVersion + 1);
    expect_rejected(newer, "version");
    // 5. Empty file.
    expect_rejected("", "magic");
}

TEST(GuidingFieldIo, StructurallyInvalidButChecksummedFilesAreRejected) {
    // Re-checksummed files whose content is inconsistent: the validation, not the checksum, must
    // catch them.
    auto rechecksum = [](std::string s) {
        s.resize(s.size() - 8);
        uint64_t h = 14695981039346656037ull;
        for (size_t i = 8; i < s.size(); ++i) h = (h ^ uint64_t(uint8_t(s[i]))) * 1099511628211ull;
        for (int i = 0; i < 8; ++i) s.push_back(char(uint8_t(h >> (8 * i))));
        return s;
    };
    const std::string good = serialize_field(make_field());
    EXPECT_NO_THROW(deserialize_field(rechecksum(good)));
    // The root's axis byte (after magic 8, version 4, bounds 24, node count 4, split 4, child 4).
    std::string bad = good;
    bad[8 + 4 + 24 + 4 + 8] = 9;
    expect_rejected(rechecksum(bad), "axis");
    // A negative fluence in the first leaf.
    const GuidingField f = make_field();
    const size_t leaves_at = 8 + 4 + 24 + 4 + f.tree().nodes().size() * 9 + 4;
    bad = good;
    const float neg = -1.f;
    std::memcpy(&bad[leaves_at], &neg, 4);
    expect_rejected(rechecksum(bad), "fluence");
}

namespace {

std::string rechecksummed(std::string s) {
    s.resize(s.size() - 8);
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 8; i < s.size(); ++i) h = (h ^ uint64_t(uint8_t(s[i]))) * 1099511628211ull;
    for (int i = 0; i < 8; ++i) s.push_back(char(uint8_t(h >> (8 * i))));
    return s;
}

// A field whose leaves are all invalid (no VMM records), so that every leaf record has the same
// size (format 3: 3 x f32 fluence, u32 samples, f32 medium fraction, u8 valid, u8 valid_indirect).
GuidingField make_vmmless_field() {
    std::vector<RadianceSample> s;
    for (int i = 0; i < 4000; ++i) {
        Sampler r(11, 0, uint64_t(i));
        s.push_back({Point3f(r.next_1d(), r.next_1d(), r.next_1d()), Vec3f(0.f, 0.f, 1.f), Color3(1.f), 1.f, false});
    }
    GuidingFieldSettings settings;
    settings.tree.max_samples = 500;
    settings.min_samples = 1 << 30;
    return GuidingField::build(BBox3f(Point3f(0.f), Point3f(1.f)), s, settings);
}

}  // namespace

TEST(GuidingFieldIo, MediumFractionsAreSavedAndVersion2FilesLoadWithoutThem) {
    GuidingField field = make_vmmless_field();
    const size_t n = field.leaves().size();
    ASSERT_GT(n, 4u);
    EXPECT_FALSE(field.has_medium_fractions());
    std::vector<float> fractions(n);
    for (size_t l = 0; l < n; ++l) fractions[l] = float(l % 5) / 4.f;  // 0, 0.25, .., 1
    field.set_medium_fractions(fractions, /*scale_fluence=*/false);
    ASSERT_TRUE(field.has_medium_fractions());

    const std::string v3 = serialize_field(field);
    const GuidingField back = deserialize_field(v3);
    ASSERT_TRUE(back.has_medium_fractions());
    for (size_t l = 0; l < n; ++l) {
        EXPECT_EQ(back.leaves()[l].medium_fraction, fractions[l]);
        EXPECT_EQ(back.leaves()[l].mostly_medium(), fractions[l] >= 0.5f);
    }

    const size_t leaves_at = 8 + 4 + 24 + 4 + field.tree().nodes().size() * 9 + 4;
    constexpr size_t kLeafV3 = 22, kFractionAt = 16;
    ASSERT_EQ(v3.size(), leaves_at + n * kLeafV3 + 8);
    // A medium fraction that is NaN or above 1 is rejected.
    for (float bad_value : {std::nanf(""), 1.5f}) {
        std::string bad = v3;
        std::memcpy(&bad[leaves_at + kFractionAt], &bad_value, 4);
        expect_rejected(rechecksummed(bad), "medium fraction");
    }

    // The same field written as version 2 (no fraction per leaf) loads with its fractions unmeasured.
    std::string v2 = v3.substr(0, leaves_at);
    v2[8] = 2;
    for (size_t l = 0; l < n; ++l) {
        const std::string leaf = v3.substr(leaves_at + l * kLeafV3, kLeafV3);
        v2 += leaf.substr(0, kFractionAt) + leaf.substr(kFractionAt + 4);
    }
    v2 += std::string(8, '\0');
    const GuidingField old = deserialize_field(rechecksummed(v2));
    EXPECT_FALSE(old.has_medium_fractions());
    ASSERT_EQ(old.leaves().size(), n);
    for (size_t l = 0; l < n; ++l) {
        EXPECT_EQ(old.leaves()[l].medium_fraction, -1.f);
        EXPECT_FALSE(old.leaves()[l].mostly_medium());
        EXPECT_EQ(old.leaves()[l].fluence, field.leaves()[l].fluence);
        EXPECT_EQ(old.leaves()[l].samples, field.leaves()[l].samples);
    }
    // Versions before 2 are rejected by name.
    std::string older = v2;
    older[8] = 1;
    expect_rejected(rechecksummed(older), "version");
}

TEST(GuidingFieldIo, MediumFractionsScaleThePerVolumeFluenceOnlyWhenAsked) {
    GuidingField scaled = make_vmmless_field(), kept = make_vmmless_field();
    std::vector<float> fractions(scaled.leaves().size(), 0.5f);
    fractions[0] = 0.f;  // a sliver the measurement missed: left unscaled
    scaled.set_medium_fractions(fractions, true);
    kept.set_medium_fractions(fractions, false);
    const GuidingField plain = make_vmmless_field();
    EXPECT_EQ(scaled.leaves()[0].fluence, plain.leaves()[0].fluence);
    for (size_t l = 1; l < fractions.size(); ++l) {
        EXPECT_EQ(scaled.leaves()[l].fluence, plain.leaves()[l].fluence * 2.f);
        EXPECT_EQ(kept.leaves()[l].fluence, plain.leaves()[l].fluence);
    }
}
