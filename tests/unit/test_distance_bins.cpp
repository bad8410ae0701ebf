// The distance decision's bins (integrators/guided/walk/distance_bins.h): the walk fused for a medium of
// one proxy (sample_constant_bins) samples exactly what the incremental sampler samples over
// BinSource's bins — the same sample, pdf and counters bit for bit and the same random numbers drawn —
// over leaves and leaf groups, from origins inside the field (with and without the origin's leaf) and
// outside it, grey and chromatic media, optically thick leaves cut into pieces, and every mixture.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "support/turning_light_field.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/vmm/phase_vmm.h"

using namespace volguide;
using namespace volguide::test;

namespace {

HomogeneousMedium medium_of(const Color3& sigma_t) {
    return HomogeneousMedium(sigma_t, std::make_shared<Volume>(VoxelGrid(Color3(0.8f)), Transform()),
                             std::make_shared<IsotropicPhase>());
}

// A segment: origins inside the box (half of them at their leaf, known to the walk) or before it.
struct Segment {
    Ray ray;
    float t_end;
    int origin_leaf;
};
std::vector<Segment> segments(const GuidingField& field, int n) {
    std::vector<Segment> out;
    const BBox3f& b = field.tree().bounds();
    for (int i = 0; i < n; ++i) {
        Sampler s(21, 0, uint64_t(i));
        const bool outside = i % 4 == 3;
        const Point3f o = outside ? Point3f(-0.5f, s.next_1d(), s.next_1d())
                                  : Point3f(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
        if (outside) d.x = std::abs(d.x) + 0.2f;
        const Ray ray(o, normalize(d));
        float t0, t1;
        if (!b.ray_intersect(ray, t0, t1) || !(t1 > 0.f)) continue;
        const float t_end = i % 3 == 0 ? 0.5f * t1 : t1;  // some segments end inside the field
        out.push_back({ray, t_end, !outside && i % 2 == 0 ? field.tree().leaf_at(o) : -1});
    }
    return out;
}

// Both walks over every segment with `settings`; `scattered` counts the decisions that scattered.
void expect_same_samples(const HomogeneousMedium& medium, const BinField& bins, const std::vector<Segment>& segs,
                         const GuidedDistanceSettings& settings, int& scattered) {
    ProxySegment proxy{};
    ASSERT_TRUE(medium.constant_proxy(proxy));
    std::vector<ProxySegment> scratch;
    scattered = 0;
    for (size_t i = 0; i < segs.size(); ++i) {
        const Segment& g = segs[i];
        Sampler a(5, 0, i), b(5, 0, i);
        BinSource source(g.ray, g.t_end, medium, bins, scratch, g.origin_leaf);
        const DistanceSample ref = sample_incremental_distance(source, a, settings);
        BinsReport report;
        const DistanceSample fused = sample_constant_bins({g.ray, g.t_end, proxy, bins, g.origin_leaf}, b, settings,
                                                          report);
        ASSERT_EQ(fused.event, ref.event) << "segment " << i;
        ASSERT_EQ(fused.t, ref.t) << "segment " << i;
        ASSERT_EQ(fused.pdf, ref.pdf) << "segment " << i;
        ASSERT_EQ(fused.pdf_transmittance, ref.pdf_transmittance) << "segment " << i;
        ASSERT_EQ(fused.pdf_guided, ref.pdf_guided) << "segment " << i;
        ASSERT_EQ(fused.steps, ref.steps) << "segment " << i;
        ASSERT_EQ(fused.strategy, ref.strategy) << "segment " << i;
        ASSERT_EQ(fused.nan_fallbacks, ref.nan_fallbacks) << "segment " << i;
        ASSERT_EQ(report.invalid, source.invalid()) << "segment " << i;
        ASSERT_EQ(report.damped, source.damped()) << "segment " << i;
        ASSERT_EQ(b.dimension(), a.dimension()) << "segment " << i;  // the same random numbers
        if (ref.event == DistanceEvent::Medium) {
            ASSERT_EQ(report.leaf, source.leaf()) << "segment " << i;
            ++scattered;
        }
    }
}

struct Fixture {
    GuidingField field = turning_light_field(5.f, 0.5f, 400, 4);
    InscatterCache cache{field, hg_phase_vmm(0.f)};
    LeafEstimates estimates{field, cache, 16};
    std::vector<float> extents = leaf_extents(field.tree());
};

}  // namespace

TEST(DistanceBins, FusedConstantWalkIsTheIncrementalSamplerOverBinSource) {
    const Fixture f;
    ASSERT_GT(f.field.tree().leaf_count(), 20);
    const std::vector<Segment> segs = segments(f.field, 1200);
    for (const Color3& sigma : {Color3(2.f), Color3(2.f, 3.f, 5.f), Color3(0.2f, 0.25f, 0.3f)}) {
        const HomogeneousMedium medium = medium_of(sigma);
        for (float c_T : {0.f, 0.5f, 1.f}) {
            GuidedDistanceSettings settings;
            settings.c_T = c_T;
            settings.channel_split = Color3(0.2f, 0.3f, 0.5f);
            const BinField bins{f.field, &f.estimates, nullptr, f.extents, 20.f, 1.f};
            int scattered = 0;
            expect_same_samples(medium, bins, segs, settings, scattered);
            if (sigma.r >= 2.f) EXPECT_GT(scattered, int(segs.size()) / 4) << sigma.r << " " << c_T;
        }
    }
}

TEST(DistanceBins, FusedConstantWalkCutsThickLeavesAsBinSource) {
    const Fixture f;
    const std::vector<Segment> segs = segments(f.field, 600);
    const HomogeneousMedium medium = medium_of(Color3(40.f, 45.f, 50.f));
    GuidedDistanceSettings settings;
    // A small optical depth per bin: every leaf is cut into several pieces; the leaves' confidence damps.
    const BinField bins{f.field, &f.estimates, nullptr, f.extents, 0.5f, 1.f};
    int scattered = 0;
    expect_same_samples(medium, bins, segs, settings, scattered);
    EXPECT_GT(scattered, int(segs.size()) / 2);
}

TEST(DistanceBins, FusedConstantWalkOverLeafGroups) {
    const Fixture f;
    const LeafGroups groups(f.field.tree(), f.estimates, f.extents, 0.3f);
    ASSERT_LT(groups.group_count(), f.field.tree().leaf_count());
    const std::vector<Segment> segs = segments(f.field, 600);
    const HomogeneousMedium medium = medium_of(Color3(2.f, 2.5f, 3.f));
    const BinField bins{f.field, &f.estimates, &groups, f.extents, 20.f, 1.f};
    int scattered = 0;
    expect_same_samples(medium, bins, segs, GuidedDistanceSettings{}, scattered);
    EXPECT_GT(scattered, 0);
}
