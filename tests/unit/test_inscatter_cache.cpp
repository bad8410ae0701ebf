// The prepared in-scattered radiance (InscatterCache) gives the field's A3 query at every point and
// direction, reads zero outside the field and in invalid leaves, is identical for any thread count,
// and stores only the lobes that exist.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/inscatter_cache.h"

using namespace volguide;

namespace {

const BBox3f kCacheBox(Point3f(0.f), Point3f(2.f, 1.f, 1.f));

// Radiance from a direction that turns with x (so leaves differ), plus a uniform part.
std::vector<RadianceSample> cache_samples(int n, uint64_t seed) {
    std::vector<RadianceSample> out;
    for (int i = 0; i < n; ++i) {
        Sampler s(seed, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const VmfLobe lobe(normalize(Vec3f(std::cos(p.x), std::sin(p.x), 0.3f)), 30.f);
        const Vec3f d = s.next_1d() < 0.7f ? lobe.sample(s.next_2d()) : warp::square_to_uniform_sphere(s.next_2d());
        out.push_back({p, d, Color3(2.f, 1.f, 0.5f)});
    }
    return out;
}

GuidingField cache_test_field() {
    GuidingFieldSettings settings;
    settings.tree.max_samples = 1500;
    settings.lobes = 6;
    return GuidingField::build(kCacheBox, cache_samples(20000, 7), settings);
}

}  // namespace

TEST(InscatterCache, EqualsTheFieldsA3Query) {
    const GuidingField field = cache_test_field();
    ASSERT_GT(field.leaves().size(), 4u);
    for (float g : {0.f, 0.5f, 0.9f, -0.3f}) {
        const PhaseVmm phase = hg_phase_vmm(g);
        const InscatterCache cache(field, phase);
        for (int i = 0; i < 500; ++i) {
            Sampler s(3, 1, uint64_t(i));
            const Point3f x(2.f * s.next_1d(), s.next_1d(), s.next_1d());
            const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
            const Color3 want = field.inscattered(x, w, phase, InscatterMode::A3);
            const Color3 got = cache.inscattered(x, w);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5f * want[c] + 1e-9f) << "g " << g << " i " << i;
            EXPECT_EQ(cache.inscattered(field.tree().leaf_at(x), w), got);
        }
    }
}

TEST(InscatterCache, ZeroOutsideAndInInvalidLeavesAndWhenEmpty) {
    GuidingFieldSettings settings;
    settings.tree.max_samples = 400;
    settings.min_samples = 100000;  // every leaf is invalid
    const GuidingField field = GuidingField::build(kCacheBox, cache_samples(3000, 9), settings);
    const InscatterCache cache(field, hg_phase_vmm(0.3f));
    int invalid = 0;
    for (size_t l = 0; l < field.leaves().size(); ++l)
        if (!field.leaves()[l].valid) {
            ++invalid;
            EXPECT_EQ(cache.inscattered(int(l), Vec3f(0.f, 0.f, 1.f)), Color3(0.f));
        }
    EXPECT_EQ(invalid, int(field.leaves().size()));
    EXPECT_EQ(cache.inscattered(Point3f(5.f, 0.f, 0.f), Vec3f(1.f, 0.f, 0.f)), Color3(0.f));
    EXPECT_EQ(cache.inscattered(-1, Vec3f(1.f, 0.f, 0.f)), Color3(0.f));
    EXPECT_EQ(InscatterCache().inscattered(Point3f(0.5f), Vec3f(1.f, 0.f, 0.f)), Color3(0.f));
}

TEST(InscatterCache, IdenticalForOneAndTwoThreadsAndCompact) {
    const GuidingField field = cache_test_field();
    const PhaseVmm phase = hg_phase_vmm(0.7f);
    InscatterCache one, two;
    tbb::task_arena(1).execute([&] { one = InscatterCache(field, phase); });
    tbb::task_arena(2).execute([&] { two = InscatterCache(field, phase); });
    for (int i = 0; i < 200; ++i) {
        Sampler s(4, 2, uint64_t(i));
        const Point3f x(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        EXPECT_EQ(one.inscattered(x, w), two.inscattered(x, w));
    }
    // At most lobes x phase lobes per valid leaf, far below the mixtures' fixed capacity.
    size_t bound = sizeof(InscatterCache) + (field.leaves().size() + 1) * sizeof(uint32_t) +
                   field.leaves().size() * 6 * size_t(phase.count) * 5 * sizeof(float);
    EXPECT_LE(one.memory_bytes(), bound);
}
