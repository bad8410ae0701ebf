#pragma once
// Minimal, independently written homogeneous medium and phase functions for testing integrators in
// isolation from the media module: analytic transmittance, exponential free flights with a channel
// chosen in proportion to the path throughput (spectral MIS, docs/theory.md §2.6), Henyey-Greenstein with Mitsuba's convention.
// load_scene_with_test_media() loads a Mitsuba XML scene whose <medium type="homogeneous"> (sigma_t,
// albedo, scale as float or rgb) and <phase type="isotropic|hg"> use these.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "volguide/core/frame.h"
#include "volguide/core/math.h"
#include "volguide/core/warp.h"
#include "volguide/media/medium.h"
#include "volguide/scene/loader.h"

namespace volguide::test {

class TestHG final : public PhaseFunction {
public:
    explicit TestHG(float g) : g_(g) {}
    float eval(const Vec3f& wi, const Vec3f& wo) const override {
        const float cos_theta = dot(-wi, wo);
        const float denom = 1.f + g_ * g_ - 2.f * g_ * cos_theta;
        return (1.f - g_ * g_) / (4.f * Pi * denom * std::sqrt(denom));
    }
    PhaseSample sample(const Vec3f& wi, Point2f u) const override {
        float cos_theta;
        if (std::abs(g_) < 1e-3f) {
            cos_theta = 1.f - 2.f * u.x;
        } else {
            const float sq = (1.f - g_ * g_) / (1.f - g_ + 2.f * g_ * u.x);
            cos_theta = (1.f + g_ * g_ - sq * sq) / (2.f * g_);
        }
        cos_theta = std::clamp(cos_theta, -1.f, 1.f);
        const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
        const float phi = 2.f * Pi * u.y;
        const Frame frame(-wi);
        PhaseSample ps;
        ps.wo = normalize(frame.to_world(Vec3f(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta)));
        ps.pdf = eval(wi, ps.wo);
        ps.weight = 1.f;
        return ps;
    }
    float mean_cosine() const override { return g_; }
    std::string to_string() const override { return "TestHG"; }

private:
    float g_;
};

class TestHomogeneousMedium final : public Medium {
public:
    TestHomogeneousMedium(const Color3& sigma_t, const Color3& albedo, std::shared_ptr<PhaseFunction> phase) {
        coeffs_.sigma_t = sigma_t;
        coeffs_.sigma_s = sigma_t * albedo;
        phase_ = std::move(phase);
    }
    MediumCoefficients eval(const Point3f&) const override { return coeffs_; }
    FreeFlightSample sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                        Sampler& sampler) const override {
        FreeFlightSample ff;
        // Channel c with probability q_c proportional to |throughput_c| (uniform if all vanish).
        Color3 q(std::abs(throughput.r), std::abs(throughput.g), std::abs(throughput.b));
        const float qsum = q.r + q.g + q.b;
        q = qsum > 0.f && std::isfinite(qsum) ? q * (1.f / qsum) : Color3(1.f / 3.f);
        float u = sampler.next_1d();
        int c = 0;
        while (c < 2 && !(u < ch(q, c))) u -= ch(q, c++);
        u = ch(q, c) > 0.f ? std::clamp(u / ch(q, c), 0.f, OneMinusEpsilon) : 0.5f;
        const float sc = ch(coeffs_.sigma_t, c);
        const float t = sc > 0.f ? -std::log1p(-u) / sc : Infinity;
        if (t < tmax) {
            const Color3 tr = tr_at(t);
            const Color3 dens = coeffs_.sigma_t * tr * q;
            ff.scattered = true;
            ff.t = t;
            ff.flight_weight = tr * (1.f / (dens.r + dens.g + dens.b));
            ff.weight = coeffs_.sigma_s * ff.flight_weight;
            ff.mi.p = ray.o + ray.d * t;
            ff.mi.t = t;
            ff.mi.wi = -ray.d;
            ff.mi.coeffs = coeffs_;
            ff.mi.medium = this;
        } else {
            const Color3 tr = tr_at(tmax);
            const float p = tr.r * q.r + tr.g * q.g + tr.b * q.b;
            ff.t = tmax;
            ff.weight = ff.flight_weight = p > 0.f ? tr * (1.f / p) : Color3(0.f);
        }
        return ff;
    }
    void sample_majorant_walk(const Ray&, float tmax, Sampler& sampler, MajorantCallback collide) const override {
        walk_constant_majorant(coeffs_.sigma_t, tmax, sampler, collide);
    }
    Color3 albedo(const Point3f&) const override {
        const Color3& st = coeffs_.sigma_t;
        return {st.r > 0.f ? coeffs_.sigma_s.r / st.r : 0.f, st.g > 0.f ? coeffs_.sigma_s.g / st.g : 0.f,
                st.b > 0.f ? coeffs_.sigma_s.b / st.b : 0.f};
    }
    Color3 transmittance(const Ray&, float tmax, Sampler&) const override { return tr_at(tmax); }
    void proxy_segments(const Ray&, float t0, float t1, std::vector<ProxySegment>& out) const override {
        const float st = coeffs_.sigma_t.average();
        if (t0 < t1) out.push_back({t0, t1, coeffs_.sigma_t, st > 0.f ? coeffs_.sigma_s.average() / st : 0.f});
    }
    bool is_homogeneous() const override { return true; }
    bool tracks_null_collisions() const override { return false; }
    BBox3f bbox() const override { return BBox3f(Point3f(-Infinity), Point3f(Infinity)); }
    std::string to_string() const override { return "TestHomogeneousMedium"; }

private:
    static float ch(const Color3& c, int i) { return i == 0 ? c.r : (i == 1 ? c.g : c.b); }
    static float tr1(float s, float t) { return s > 0.f ? std::exp(-s * t) : 1.f; }
    Color3 tr_at(float t) const {
        return Color3(tr1(coeffs_.sigma_t.r, t), tr1(coeffs_.sigma_t.g, t), tr1(coeffs_.sigma_t.b, t));
    }
    MediumCoefficients coeffs_;
};

inline ObjectPtr test_media_factory(const std::string& tag, const Properties& props) {
    if (tag == "phase") {
        if (props.type() == "isotropic") return std::make_shared<TestHG>(0.f);
        if (props.type() == "hg") return std::make_shared<TestHG>(props.get_float("g", 0.8f));
    }
    if (tag == "medium" && props.type() == "homogeneous") {
        const float scale = props.get_float("scale", 1.f);
        const Color3 sigma_t = props.get_color("sigma_t", Color3(1.f)) * scale;
        const Color3 albedo = props.get_color("albedo", Color3(0.75f));
        std::shared_ptr<PhaseFunction> phase = std::make_shared<TestHG>(0.f);
        auto phases = props.children("phase");
        if (!phases.empty()) phase = std::dynamic_pointer_cast<PhaseFunction>(std::get<ObjectPtr>(phases[0]->value));
        return std::make_shared<TestHomogeneousMedium>(sigma_t, albedo, phase);
    }
    return create_object(tag, props);
}

inline std::unique_ptr<Scene> load_scene_with_test_media(const std::string& path, const LoadOptions& options = {}) {
    return make_scene(load_scene_properties(path, options, test_media_factory));
}

}  // namespace volguide::test
