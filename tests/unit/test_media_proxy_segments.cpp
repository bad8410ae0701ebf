// Proxy coefficients for guided distance sampling (docs/theory.md §7.7 H1): segments tile the requested
// interval in order, a homogeneous medium gives one exact segment, and a heterogeneous medium's
// proxy optical depth (cell means) follows the true optical depth along rays through a cloud.
#include <gtest/gtest.h>

#include "support/media_test_util.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_isotropic.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::shared_ptr<HeterogeneousMedium> cloud(int channels) {
    Transform to_world = Transform::translate(Vec3f(-1.f, -0.6f, -0.4f)) * Transform::rotate(Vec3f(0, 0, 1), 30.f) *
                         Transform::scale(Vec3f(2.f, 1.5f, 1.f));
    auto sigma = std::make_shared<Volume>(
        VoxelGrid(procedural_cloud(24, 20, 16, channels), VolumeFilter::Trilinear, VolumeWrap::Clamp), to_world);
    auto albedo = std::make_shared<Volume>(VoxelGrid(Color3(0.8f, 0.6f, 0.4f)), Transform());
    return std::make_shared<HeterogeneousMedium>(sigma, 4.f, albedo, std::make_shared<IsotropicPhase>());
}

void expect_tiling(const std::vector<ProxySegment>& s, float t0, float t1) {
    ASSERT_FALSE(s.empty());
    EXPECT_EQ(s.front().t0, t0);
    EXPECT_EQ(s.back().t1, t1);
    for (size_t i = 0; i < s.size(); ++i) {
        EXPECT_LT(s[i].t0, s[i].t1) << i;
        if (i > 0) {
            EXPECT_EQ(s[i].t0, s[i - 1].t1) << i;
        }
        EXPECT_GE(s[i].albedo, 0.f);
        EXPECT_LE(s[i].albedo, 1.f);
    }
}

}  // namespace

TEST(MediaProxySegments, HomogeneousIsOneExactSegment) {
    HomogeneousMedium m(Color3(1.f, 2.f, 3.f), std::make_shared<Volume>(VoxelGrid(Color3(0.5f)), Transform()),
                        std::make_shared<IsotropicPhase>());
    std::vector<ProxySegment> s;
    m.proxy_segments(Ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f)), 0.5f, 4.f, s);
    ASSERT_EQ(s.size(), 1u);
    expect_tiling(s, 0.5f, 4.f);
    EXPECT_EQ(s[0].sigma_t, Color3(1.f, 2.f, 3.f));
    EXPECT_FLOAT_EQ(s[0].albedo, 0.5f);
    s.clear();
    m.proxy_segments(Ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f)), 2.f, 2.f, s);
    EXPECT_TRUE(s.empty());
}

TEST(MediaProxySegments, HeterogeneousFollowsTheOpticalDepth) {
    for (int channels : {1, 3}) {
        const auto m = cloud(channels);
        const Ray rays[] = {Ray(Point3f(-3.f, 0.55f, 0.15f), normalize(Vec3f(1.f, 0.f, 0.01f))),
                            Ray(Point3f(-1.5f, -0.8f, -1.f), normalize(Vec3f(1.f, 1.35f, 1.15f))),
                            Ray(Point3f(-0.5f, 0.3f, 0.1f), normalize(Vec3f(-0.3f, 1.f, 0.2f)))};
        for (const Ray& ray : rays) {
            std::vector<ProxySegment> s;
            m->proxy_segments(ray, 0.1f, 8.f, s);
            expect_tiling(s, 0.1f, 8.f);
            EXPECT_GT(s.size(), 5u);  // cut at the majorant cells
            // Proxy vs true optical depth (midpoint quadrature, 20000 steps).
            double proxy = 0, truth = 0;
            for (const ProxySegment& p : s) proxy += double(p.sigma_t.average()) * (p.t1 - p.t0);
            const int n = 20000;
            const double dt = (8.0 - 0.1) / n;
            for (int i = 0; i < n; ++i) truth += m->eval(ray(float(0.1 + (i + 0.5) * dt))).sigma_t.average() * dt;
            ASSERT_GT(truth, 0.5);
            // The cell mean is taken over every voxel a lookup in the cell can read (one beyond its
            // edges), so it smooths peaks: a ray through the cloud's core reads ~22 % low. A proxy
            // only shapes probabilities; 30 % still catches a wrong cell, scale or channel.
            EXPECT_NEAR(proxy, truth, 0.3 * truth) << "channels " << channels;
            // Albedo proxy of a constant albedo: the channel-weighted mean sigma_s / sigma_t.
            for (const ProxySegment& p : s)
                if (p.sigma_t.average() > 0.f && channels == 1) {
                    EXPECT_NEAR(p.albedo, 0.6f, 1e-4f);
                }
        }
    }
}
