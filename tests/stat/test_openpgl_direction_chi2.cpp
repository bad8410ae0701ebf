// Chi-square of openpgl_volpath's direction samplers (src/volguide/integrators/openpgl/openpgl_walk_policy.h)
// against their own mixture pdfs, with the weight check eval / pdf:
//  - medium vertex: Open PGL's VolumeSamplingDistribution times the HG lobe, mixed with HG
//    sampling (phase_prob 0.5 and 0.2), for g in {0, 0.6, -0.4};
//  - surface vertex: SurfaceSamplingDistribution times the cosine lobe, mixed with a diffuse BSDF
//    (bsdf_prob 0.5 and 0.2), in the local frame of a tilted shading normal;
//  - a control: the guided samples are rejected against the phase function's pdf alone (so the
//    field does guide, and the test can fail).
// The field is trained directly from synthetic samples (two lobes of incident light, one region),
// not from a render: the test is about the sampler and its pdf, whatever the field learned.
// Skipped without Open PGL.
#include <gtest/gtest.h>

#if VOLGUIDE_HAVE_OPENPGL
#include <fmt/format.h>

#include <memory>
#include <ostream>
#include <random>
#include <vector>

#include "support/bsdf_helpers.h"
#include "support/chi2.h"
#include "support/test_media.h"
#include "volguide/media/phase_hg.h"
#include "volguide/integrators/openpgl/openpgl_walk_policy.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Incident light in the unit box: 70 % from around a1, 30 % from around a2 (Open PGL's directions
// point towards where the radiance comes from), one Update of `n` volume and `n` surface samples.
std::unique_ptr<OpenPglField> trained_field(int n = 20000) {
    auto field = std::make_unique<OpenPglField>(BBox3f(Point3f(-1.f), Point3f(1.f)), 1, 32000);
    const Vec3f a1 = normalize(Vec3f(0.2f, 0.3f, 0.9f)), a2 = normalize(Vec3f(-0.8f, 0.1f, -0.3f));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(-1.f, 1.f), u01(0.f, 1.f);
    std::normal_distribution<float> normal(0.f, 1.f);
    std::vector<openpgl::cpp::SampleData> samples;
    for (int i = 0; i < 2 * n; ++i) {
        const Vec3f axis = u01(rng) < 0.7f ? a1 : a2;
        const Vec3f d = normalize(axis + 0.25f * Vec3f(normal(rng), normal(rng), normal(rng)));
        openpgl::cpp::SampleData s{};
        s.position = pgl_point(Point3f(uniform(rng), uniform(rng), uniform(rng)) * 0.5f);
        s.direction = pgl_vec(d);
        s.weight = 1.f;
        s.pdf = 1.f / (4.f * Pi);
        s.distance = 2.f;
        s.flags = i < n ? uint32_t(openpgl::cpp::SampleData::EInsideVolume) : 0u;
        samples.push_back(s);
    }
    field->add_samples(samples.data(), samples.size());
    field->update();
    return field;
}

OpenPglField& field() {
    static const std::unique_ptr<OpenPglField> f = trained_field();
    return *f;
}

struct VolumeCase {
    float g;
    float phase_prob;
};

void PrintTo(const VolumeCase& c, std::ostream* os) {
    *os << fmt::format("g{}_phase_prob{}", c.g, c.phase_prob);
}

std::vector<VolumeCase> volume_cases() {
    std::vector<VolumeCase> out;
    for (float g : {0.f, 0.6f, -0.4f})
        for (float p : {0.5f, 0.2f}) out.push_back({g, p});
    return out;
}

const std::vector<float> kSurfaceBsdfProbs = {0.5f, 0.2f};
const int kOpenPglTestCount = int(volume_cases().size() + kSurfaceBsdfProbs.size()) + 1;  // + the control

ChiSquareOptions openpgl_options(uint64_t seed) {
    ChiSquareOptions opt;
    opt.test_count = kOpenPglTestCount;
    opt.seed = seed;
    opt.weight_check_count = 100000;
    return opt;
}

// One medium vertex inside the trained region, its policy prepared (the region chosen once).
struct MediumVertex {
    explicit MediumVertex(const VolumeCase& c)
        : medium(Color3(1.f), Color3(0.8f), std::make_shared<HGPhase>(c.g)), ts(&field().field()) {
        settings.phase_prob = c.phase_prob;
        mi.p = Point3f(0.1f, 0.2f, -0.1f);
        mi.wi = normalize(Vec3f(0.4f, -0.5f, 0.3f));
        mi.medium = &medium;
        policy = std::make_unique<OpenPglWalkPolicy>(settings, ts, field());
        Sampler s(3, 0, 0);
        policy->begin_vertex(mi);
        policy->prepare_direction(mi, s);
    }
    TestHomogeneousMedium medium;
    OpenPglSettings settings;
    OpenPglThreadState ts;
    MediumInteraction mi;
    std::unique_ptr<OpenPglWalkPolicy> policy;
};

class OpenPglVolumeChi2 : public ::testing::TestWithParam<VolumeCase> {};

}  // namespace

TEST_P(OpenPglVolumeChi2, MixtureMatchesItsPdf) {
    MediumVertex v(GetParam());
    ASSERT_EQ(v.ts.guided_medium, 1) << "Open PGL's region lookup failed: the vertex is not guided";
    const ChiSquareResult r = chi2_test_sphere(
        [&](Sampler& s) {
            const PhaseSample ps = v.policy->sample_direction(v.mi, s, nullptr);
            return ChiSquareSample{ps.wo, Color3(ps.weight), ps.pdf > 0.f};
        },
        [&](const Vec3f& d) { return double(v.policy->direction_pdf(v.mi, d)); }, openpgl_options(11),
        [&](const Vec3f& d) { return Color3(v.medium.phase().eval(v.mi.wi, d)); });
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Cases, OpenPglVolumeChi2, ::testing::ValuesIn(volume_cases()));

// The guided mixture is not the phase function: against HG's pdf alone it is rejected.
TEST(OpenPglVolumeChi2, GuidedSamplesAreNotPhaseSamples) {
    MediumVertex v({0.f, 0.5f});
    ASSERT_EQ(v.ts.guided_medium, 1);
    const ChiSquareResult r = chi2_test_sphere(
        [&](Sampler& s) {
            const PhaseSample ps = v.policy->sample_direction(v.mi, s, nullptr);
            return ChiSquareSample{ps.wo, Color3(1.f), ps.pdf > 0.f};
        },
        [&](const Vec3f& d) { return double(v.medium.phase().pdf(v.mi.wi, d)); }, openpgl_options(12));
    EXPECT_FALSE(r.passed) << r.report;
}

TEST(OpenPglSurfaceChi2, MixtureWithDiffuseMatchesItsPdf) {
    const auto bsdf = make_bsdf("diffuse", {{"reflectance", 0.7f}});
    SurfaceInteraction si;
    si.t = 1.f;
    si.p = Point3f(-0.1f, 0.1f, 0.2f);
    si.sh_frame = Frame(normalize(Vec3f(0.3f, -0.2f, 0.93f)));
    si.n = Normal3f(si.sh_frame.n);
    si.wi = normalize(Vec3f(0.2f, 0.4f, 0.8f));  // local, on the normal's side
    si.uv = Vec2f(0.3f, 0.6f);
    const BSDFContext ctx;
    uint64_t seed = 20;
    for (float bsdf_prob : kSurfaceBsdfProbs) {
        SCOPED_TRACE(fmt::format("bsdf_prob {}", bsdf_prob));
        OpenPglSettings settings;
        settings.bsdf_prob = bsdf_prob;
        OpenPglThreadState ts(&field().field());
        OpenPglWalkPolicy policy(settings, ts, field());
        Sampler prep(5, 0, 0);
        policy.prepare_surface_direction(si, *bsdf, nullptr, prep);
        ASSERT_EQ(ts.guided_surface, 1) << "Open PGL's region lookup failed: the vertex is not guided";
        const ChiSquareResult r = chi2_test_sphere(
            [&](Sampler& s) {
                const float u1 = s.next_1d();
                const Point2f u2 = s.next_2d();
                const auto [bs, weight] = policy.sample_surface_direction(SurfaceQuery{ctx, si, *bsdf}, u1, u2, s, nullptr);
                return ChiSquareSample{bs.wo, weight, bs.pdf > 0.f};
            },
            [&](const Vec3f& wo) { return double(policy.surface_direction_pdf(SurfaceQuery{ctx, si, *bsdf}, wo)); },
            openpgl_options(seed++), [&](const Vec3f& wo) { return bsdf->eval(ctx, si, wo); });
        EXPECT_TRUE(r.passed) << r.report;
    }
}

#else
TEST(OpenPglDirectionChi2, Skipped) {
    GTEST_SKIP() << "volguide was built without Intel Open PGL: openpgl_volpath is not available";
}
#endif
