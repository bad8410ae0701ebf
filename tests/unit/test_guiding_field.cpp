// The guiding field built from radiance samples (no scene): per-leaf VMMs point where the radiance
// comes from, fluence follows the collision estimator, queries are Phi * V_L and Phi * (V_L * phase),
// sparse leaves are invalid, and the field is identical for 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cstring>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/guiding_field.h"

using namespace volguide;

namespace {

const BBox3f kFieldBox(Point3f(0.f), Point3f(2.f, 1.f, 1.f));

// Radiance arriving mostly from `towards` (a kappa-20 lobe) plus a uniform part; weight 3 per sample.
std::vector<RadianceSample> field_samples(int n, const Vec3f& towards, uint64_t seed) {
    std::vector<RadianceSample> out;
    const VmfLobe lobe(towards, 20.f);
    for (int i = 0; i < n; ++i) {
        Sampler s(seed, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Vec3f d =
            s.next_1d() < 0.8f ? lobe.sample(s.next_2d()) : warp::square_to_uniform_sphere(s.next_2d());
        out.push_back({p, d, Color3(3.f, 2.f, 1.f)});
    }
    return out;
}

GuidingFieldSettings small_leaves() {
    GuidingFieldSettings s;
    s.tree.max_samples = 2000;
    s.lobes = 4;
    return s;
}

}  // namespace

TEST(GuidingField, LeafMixturesPointTowardsTheLight) {
    const Vec3f towards = normalize(Vec3f(1.f, 0.2f, -0.1f));
    GuidingField field = GuidingField::build(kFieldBox, field_samples(20000, towards, 1), small_leaves());
    ASSERT_GE(field.leaves().size(), 8u);
    for (const GuidingLeaf& leaf : field.leaves()) {
        ASSERT_TRUE(leaf.valid);
        const Vec3f mean = leaf.vmm.mean_vector();
        EXPECT_GT(dot(normalize(mean), towards), 0.95f);
        // The density is much higher towards the light than away from it.
        EXPECT_GT(leaf.vmm.pdf(towards), 20.f * leaf.vmm.pdf(-towards));
    }
}

TEST(GuidingField, IndirectMixturesLeaveOutDirectSamples) {
    // Direct light (a photon's first collision) from +x, the rest from +z.
    const Vec3f light = Vec3f(1.f, 0.f, 0.f), bounce = Vec3f(0.f, 0.f, 1.f);
    auto direct = field_samples(12000, light, 3), rest = field_samples(12000, bounce, 4);
    for (RadianceSample& s : direct) s.direct = true;
    std::vector<RadianceSample> all = direct;
    all.insert(all.end(), rest.begin(), rest.end());
    const GuidingField field = GuidingField::build(kFieldBox, all, small_leaves());
    ASSERT_GE(field.leaves().size(), 8u);
    for (const GuidingLeaf& leaf : field.leaves()) {
        ASSERT_TRUE(leaf.valid);
        ASSERT_TRUE(leaf.valid_indirect);
        // The full mixture has both lobes; the indirect one only the bounce.
        EXPECT_GT(leaf.vmm.pdf(light), 3.f * leaf.vmm.pdf(-light));
        EXPECT_GT(leaf.vmm.pdf(bounce), 3.f * leaf.vmm.pdf(-bounce));
        EXPECT_GT(dot(normalize(leaf.vmm_indirect.mean_vector()), bounce), 0.95f);
        EXPECT_LT(leaf.vmm_indirect.pdf(light), 0.1f * leaf.vmm_indirect.pdf(bounce));
    }
    // Without direct flags (camera-path training) the indirect mixture is the full one.
    const GuidingField plain = GuidingField::build(kFieldBox, rest, small_leaves());
    for (const GuidingLeaf& leaf : plain.leaves()) {
        EXPECT_EQ(leaf.valid_indirect, leaf.valid);
        EXPECT_EQ(leaf.vmm_indirect.pdf(light), leaf.vmm.pdf(light));
    }
}

TEST(GuidingField, PerVolumeFluenceIsTheCollisionEstimator) {
    const auto s = field_samples(20000, Vec3f(0.f, 0.f, 1.f), 2);
    GuidingField field = GuidingField::build(kFieldBox, s, small_leaves());
    // Sum over leaves of Phi * volume = sum of the weights (per channel), and uniform positions
    // give about the same fluence everywhere: 20000 * 3 / 2 = 30000 in the red channel.
    double total[3] = {0, 0, 0};
    for (int l = 0; l < field.tree().leaf_count(); ++l) {
        const Vec3f e = field.tree().leaf_bounds(l).extents();
        const double v = double(e.x) * e.y * e.z;
        for (int c = 0; c < 3; ++c) total[c] += field.leaves()[size_t(l)].fluence[c] * v;
        EXPECT_NEAR(field.leaves()[size_t(l)].fluence.r, 30000.f, 30000.f * 0.15f) << "leaf " << l;
    }
    EXPECT_NEAR(total[0], 60000.0, 1.0);
    EXPECT_NEAR(total[1], 40000.0, 1.0);
    EXPECT_NEAR(total[2], 20000.0, 1.0);
}

TEST(GuidingField, PerSampleMeanFluence) {
    auto settings = small_leaves();
    settings.fluence = FluenceEstimator::PerSampleMean;
    GuidingField field = GuidingField::build(kFieldBox, field_samples(5000, Vec3f(0.f, 1.f, 0.f), 3), settings);
    for (const GuidingLeaf& leaf : field.leaves()) EXPECT_EQ(leaf.fluence, Color3(3.f, 2.f, 1.f));
}

TEST(GuidingField, QueriesAreFluenceTimesMixture) {
    GuidingField field = GuidingField::build(kFieldBox, field_samples(10000, Vec3f(1.f, 0.f, 0.f), 4), small_leaves());
    const Point3f x(0.3f, 0.6f, 0.2f);
    const GuidingLeaf* leaf = field.leaf_at(x);
    ASSERT_NE(leaf, nullptr);
    const Vec3f w = normalize(Vec3f(1.f, 0.3f, 0.f));
    const Color3 li = field.incident(x, w);
    EXPECT_FLOAT_EQ(li.g, leaf->fluence.g * leaf->vmm.pdf(w));
    // Isotropic medium: in-scattered radiance is Phi / (4 pi) in every direction (docs/theory.md §5.6).
    const PhaseVmm iso = hg_phase_vmm(0.f);
    for (const Vec3f& d : {Vec3f(1.f, 0.f, 0.f), Vec3f(0.f, 0.f, -1.f)}) {
        const Color3 ls = field.inscattered(x, d, iso);
        EXPECT_NEAR(ls.r, leaf->fluence.r * InvFourPi, 1e-4f * leaf->fluence.r);
    }
    // Forward scattering (docs/theory.md §1.1): for a ray travelling along d, L_i(d) = int f(d, w') L(w') dw'
    // with f centred on w' = d, so it is largest when d points towards the light (+x).
    const PhaseVmm fwd = hg_phase_vmm(0.8f);
    const Color3 towards = field.inscattered(x, Vec3f(1.f, 0.f, 0.f), fwd);
    const Color3 away = field.inscattered(x, Vec3f(-1.f, 0.f, 0.f), fwd);
    EXPECT_GT(towards.r, 5.f * away.r);
    // The A3 approximation stays within 10 % of the exact convolution near the peak.
    const Color3 approx = field.inscattered(x, Vec3f(1.f, 0.f, 0.f), fwd, InscatterMode::A3);
    EXPECT_NEAR(approx.r, towards.r, 0.1f * towards.r);
    // Outside the field: nothing.
    EXPECT_EQ(field.incident(Point3f(5.f, 0.f, 0.f), w), Color3(0.f));
    EXPECT_EQ(field.leaf_at(Point3f(5.f, 0.f, 0.f)), nullptr);
}

TEST(GuidingField, SparseLeavesAreInvalidAndReadZero) {
    auto settings = small_leaves();
    settings.min_samples = 64;
    auto s = field_samples(60, Vec3f(0.f, 0.f, 1.f), 5);
    GuidingField field = GuidingField::build(kFieldBox, s, settings);
    ASSERT_EQ(field.leaves().size(), 1u);
    EXPECT_FALSE(field.leaves()[0].valid);
    EXPECT_GT(field.leaves()[0].fluence.r, 0.f);  // fluence is still estimated
    EXPECT_EQ(field.incident(Point3f(0.5f), Vec3f(0.f, 0.f, 1.f)), Color3(0.f));
    // Zero-weight samples do not count towards validity.
    for (auto& r : s) r.weight = Color3(0.f);
    s.resize(60);
    for (int i = 0; i < 100; ++i) s.push_back(s[0]);
    EXPECT_FALSE(GuidingField::build(kFieldBox, s, settings).leaves()[0].valid);
}

// Progressive training in thin fog: camera vertices fill the volume uniformly and only those in a
// light shaft carry radiance. The tree refines by the radiance-carrying samples, so the shaft's leaves
// hold enough of them to be valid (when every sample counted, a shaft with 10 % of the vertices got
// leaves of 300 samples with ~30 non-zero ones: all invalid, the field read 0 there). The per-sample
// mean still counts the zeros: sum over leaves of fluence * samples = sum of the weights.
TEST(GuidingField, ALightShaftAmongZeroSamplesGetsValidLeaves) {
    std::vector<RadianceSample> s;
    double total = 0;
    for (int i = 0; i < 20000; ++i) {
        Sampler r(11, 0, uint64_t(i));
        const Point3f p(2.f * r.next_1d(), r.next_1d(), r.next_1d());
        const bool lit = p.x > 0.9f && p.x < 1.1f;
        const Vec3f d = VmfLobe(Vec3f(0.f, 0.f, 1.f), 50.f).sample(r.next_2d());
        s.push_back({p, d, lit ? Color3(5.f) : Color3(0.f), 1.f});
        total += lit ? 5.0 : 0.0;
    }
    GuidingFieldSettings settings;
    settings.tree.max_samples = 300;
    settings.lobes = 2;
    settings.fluence = FluenceEstimator::PerSampleMean;
    const GuidingField field = GuidingField::build(kFieldBox, s, settings);
    double sum = 0;
    for (const GuidingLeaf& leaf : field.leaves()) sum += double(leaf.fluence.r) * leaf.samples;
    EXPECT_NEAR(sum, total, 1e-4 * total);
    for (int i = 0; i < 50; ++i) {
        Sampler r(12, 0, uint64_t(i));
        const Point3f x(0.9f + 0.2f * r.next_1d(), r.next_1d(), r.next_1d());
        const GuidingLeaf* leaf = field.leaf_at(x);
        ASSERT_NE(leaf, nullptr);
        EXPECT_TRUE(leaf->valid) << "at " << x.x << " " << x.y << " " << x.z;
        EXPECT_GT(field.incident(x, Vec3f(0.f, 0.f, 1.f)).r, 0.f);
    }
}

TEST(GuidingField, IdenticalForOneAndTwoThreads) {
    const auto s = field_samples(30000, normalize(Vec3f(0.f, 1.f, 1.f)), 6);
    auto settings = small_leaves();
    GuidingField a, b;
    tbb::task_arena(1).execute([&] { a = GuidingField::build(kFieldBox, s, settings); });
    tbb::task_arena(2).execute([&] { b = GuidingField::build(kFieldBox, s, settings); });
    ASSERT_EQ(a.leaves().size(), b.leaves().size());
    for (size_t l = 0; l < a.leaves().size(); ++l) {
        const GuidingLeaf &la = a.leaves()[l], &lb = b.leaves()[l];
        ASSERT_EQ(la.vmm.count, lb.vmm.count);
        EXPECT_EQ(std::memcmp(&la.vmm, &lb.vmm, sizeof(Vmm)), 0) << "leaf " << l;
        EXPECT_EQ(la.fluence, lb.fluence);
    }
}

