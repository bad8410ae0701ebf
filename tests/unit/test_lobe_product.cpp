// The compact lobe blocks and the vectorised product (vmm/lobe_block.h, vmm/lobe_product.h,
// vmm/vmf_simd.h) against the scalar double-precision reference (vmm.h's VmfMixture::pdf and
// product_into): the block's density, the product's pair weights, lobes and integral, its factorised
// pdf against the pairs' mixture pdf, every Highway target the CPU runs against the others, extreme
// concentrations, and the store's memory.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/lobe_block.h"
#include "volguide/vmm/lobe_product.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/vmf_simd.h"

using namespace volguide;

namespace {

// A normalised mixture of n lobes, concentrations log-uniform in [0.01, max_kappa].
Vmm random_mixture(int n, float max_kappa, uint64_t seed) {
    Sampler s(seed, 0, 0);
    Vmm m;
    for (int k = 0; k < n; ++k) {
        const float kappa = 0.01f * std::pow(max_kappa / 0.01f, s.next_1d());
        m.add_lobe(0.05f + s.next_1d(), VmfLobe(warp::square_to_uniform_sphere(s.next_2d()), kappa));
    }
    m.normalize_weights();
    return m;
}

struct Block {
    alignas(64) std::array<float, kLobeArrays * kVmmMaxLobes> data;
    LobeBlock view;
    explicit Block(const Vmm& m) { view = write_lobe_block(m, data.data()); }
};

// Directions: random ones and ones near each lobe's axis (where concentrated lobes have their mass).
std::vector<Vec3f> test_directions(const Vmm& m, uint64_t seed) {
    Sampler s(seed, 1, 0);
    std::vector<Vec3f> w;
    for (int i = 0; i < 64; ++i) w.push_back(warp::square_to_uniform_sphere(s.next_2d()));
    for (int k = 0; k < m.count; ++k) w.push_back(m.lobe(k).sample(s.next_2d()));
    return w;
}

const float kGs[] = {0.3f, 0.7f, 0.9f, -0.6f};
const int kLobeCounts[] = {1, 3, 8, 13, 32};

}  // namespace

TEST(LobeBlock, DensityIsTheMixturePdf) {
    for (int n : kLobeCounts) {
        const Vmm m = random_mixture(n, 3000.f, uint64_t(n));
        const Block b(m);
        ASSERT_EQ(b.view.padded % kLobeLanes, 0);
        for (const Vec3f& w : test_directions(m, 7)) {
            const float want = m.pdf(w), got = lobe_block_eval(b.view, w).value();
            EXPECT_NEAR(got, want, 2e-5f * want + 1e-30f) << n << " lobes";
        }
    }
}

TEST(LobeProduct, PairsMatchTheDoubleProduct) {
    for (int n : kLobeCounts)
        for (float g : kGs) {
            const Vmm m = random_mixture(n, 500.f, uint64_t(10 + n));
            const Block b(m);
            const PhaseVmm phase = hg_phase_vmm(g);
            const PhaseLobes lobes = prepare_phase_lobes(phase);
            const Vec3f d = normalize(Vec3f(0.3f, -0.2f, 0.9f));
            LobeProduct p;
            ASSERT_TRUE(p.build(b.view, lobes, d));
            double z_ref = 0.0;
            const auto ref = product(m, phase.oriented(d), &z_ref);
            EXPECT_NEAR(p.integral(), z_ref, 1e-4 * z_ref) << n << " lobes, g " << g;
            const auto got = p.mixture();
            ASSERT_EQ(got.count, ref.count);
            for (int i = 0; i < ref.count; ++i) {
                EXPECT_NEAR(got.weight[i], ref.weight[i], 1e-4f * ref.weight[i] + 1e-7f) << "pair " << i;
                EXPECT_NEAR(got.kappa[i], ref.kappa[i], 1e-4f * ref.kappa[i] + 1e-5f) << "pair " << i;
                if (ref.kappa[i] > 1e-3f) {
                    EXPECT_GT(dot(got.lobe(i).mu, ref.lobe(i).mu), 1.f - 1e-5f) << "pair " << i;
                }
            }
        }
}

TEST(LobeProduct, FactorisedPdfIsThePairsPdf) {
    for (int n : kLobeCounts)
        for (float g : kGs) {
            const Vmm m = random_mixture(n, 2000.f, uint64_t(20 + n));
            const Block b(m);
            const PhaseLobes lobes = prepare_phase_lobes(hg_phase_vmm(g));
            const Vec3f d = normalize(Vec3f(-0.5f, 0.1f, 0.4f));
            LobeProduct p;
            ASSERT_TRUE(p.build(b.view, lobes, d));
            const auto mixture = p.mixture();
            Sampler s(3, 0, uint64_t(n));
            for (int i = 0; i < 200; ++i) {
                const Vec3f w = i % 2 ? p.sample(s.next_2d()) : warp::square_to_uniform_sphere(s.next_2d());
                const float want = mixture.pdf(w), got = p.pdf(w);
                EXPECT_NEAR(got, want, 1e-4f * want + 1e-30f) << n << " lobes, g " << g;
            }
        }
}

// 500 random 8-lobe mixtures, concentrations log-uniform over [1e-3, 1e3], times random HG lobes:
// weights, concentrations and the integral against the double reference.
TEST(LobeProduct, RandomMixturesMatchTheDoubleProduct) {
    for (int trial = 0; trial < 500; ++trial) {
        Sampler s(17, 0, uint64_t(trial));
        Vmm a;
        for (int k = 0; k < 8; ++k)
            a.add_lobe(0.05f + s.next_1d(), VmfLobe(warp::square_to_uniform_sphere(s.next_2d()),
                                                    std::exp(std::log(1e-3f) + s.next_1d() * std::log(1e6f))));
        a.normalize_weights();
        const PhaseVmm phase = hg_phase_vmm(-0.95f + 1.9f * s.next_1d());
        const Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
        const Block b(a);
        const PhaseLobes lobes = prepare_phase_lobes(phase);
        LobeProduct p;
        ASSERT_TRUE(p.build(b.view, lobes, d)) << trial;
        double z_ref = 0.0;
        const auto ref = product(a, phase.oriented(d), &z_ref);
        EXPECT_NEAR(p.integral(), z_ref, 1e-4 * z_ref) << trial;
        const auto got = p.mixture();
        ASSERT_EQ(got.count, ref.count) << trial;
        for (int k = 0; k < ref.count; ++k) {
            EXPECT_NEAR(got.weight[k], ref.weight[k], 1e-4 * ref.weight[k] + 1e-6) << trial << " lobe " << k;
            EXPECT_NEAR(got.kappa[k], ref.kappa[k], 1e-4 * ref.kappa[k] + 1e-4) << trial;
        }
    }
}

// Two concentrated lobes far apart: every pair's mass is far below float range, the product keeps
// its shape (the masses are taken relative to the largest) and its pdf stays the pairs' pdf.
TEST(LobeProduct, FarApartConcentratedLobesKeepTheirShape) {
    Vmm m;
    m.add_lobe(0.5f, VmfLobe(Vec3f(1.f, 0.f, 0.f), 20000.f));
    m.add_lobe(0.5f, VmfLobe(normalize(Vec3f(1.f, 0.1f, 0.f)), 30000.f));
    const Block b(m);
    const PhaseLobes lobes = prepare_phase_lobes(hg_phase_vmm(0.99f));
    const Vec3f d(0.f, 0.f, 1.f);
    LobeProduct p;
    ASSERT_TRUE(p.build(b.view, lobes, d));
    EXPECT_GT(p.integral(), 0.0);
    const auto mixture = p.mixture();
    Sampler s(5, 0, 0);
    for (int i = 0; i < 100; ++i) {
        const Vec3f w = p.sample(s.next_2d());
        const float got = p.pdf(w);
        ASSERT_TRUE(std::isfinite(got) && got > 0.f);
        EXPECT_NEAR(got, mixture.pdf(w), 2e-3f * got);
    }
}

// Runtime dispatch: the product and the block density on every target this CPU supports (SSSE3,
// SSE4, AVX2, AVX-512, ...) agree to float rounding.
TEST(LobeProduct, EveryTargetAgrees) {
    const Vmm m = random_mixture(13, 1000.f, 99);
    const Block b(m);
    const PhaseLobes lobes = prepare_phase_lobes(hg_phase_vmm(0.8f));
    const Vec3f d = normalize(Vec3f(0.2f, 0.6f, -0.7f));
    const std::vector<Vec3f> dirs = test_directions(m, 11);
    std::vector<float> first;
    const auto targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        LobeProduct p;
        ASSERT_TRUE(p.build(b.view, lobes, d)) << hwy::TargetName(target);
        std::vector<float> values{float(p.integral())};
        for (const Vec3f& w : dirs) {
            values.push_back(p.pdf(w));
            values.push_back(lobe_block_eval(b.view, w).value());
        }
        if (first.empty()) first = values;
        for (size_t i = 0; i < values.size(); ++i)
            EXPECT_NEAR(values[i], first[i], 1e-5f * first[i] + 1e-30f) << hwy::TargetName(target) << " value " << i;
    }
    hwy::SetSupportedTargetsForTest(0);
}

TEST(LobeStore, BlocksAtTheirOwnLobeCount) {
    const Vmm eight = random_mixture(8, 100.f, 1), three = random_mixture(3, 100.f, 2);
    const Vmm* mixtures[] = {&eight, &three, &eight};
    const uint8_t valid[] = {1, 1, 0};
    const LobeStore store(mixtures, valid);
    ASSERT_EQ(store.size(), 3u);
    EXPECT_EQ(store.block(0).count, 8);
    EXPECT_EQ(store.block(1).count, 3);
    EXPECT_TRUE(store.block(2).empty());
    for (int i = 0; i < 2; ++i) EXPECT_EQ(reinterpret_cast<uintptr_t>(store.block(i).data) % 64, 0u);
    // An 8-lobe block is 7 arrays of 8 floats (224 bytes), 256 with its alignment: a third of a
    // 32-lobe VmfMixture (772 bytes).
    EXPECT_LE(store.bytes(), 2 * 256 + 3 * 8 + 64);
    const Vec3f w = normalize(Vec3f(1.f, 2.f, 3.f));
    EXPECT_NEAR(lobe_block_eval(store.block(0), w).value(), eight.pdf(w), 1e-5f * eight.pdf(w));
}
