#pragma once
// Helpers for BSDF tests: building plugins from parameters and adapting them to the chi-square
// harness.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "support/chi2.h"
#include "volguide/core/properties.h"
#include "volguide/render/bsdf.h"
#include "volguide/scene/factories.h"

namespace volguide::test {

// One parameter: name and value (double = <float>, std::string = <string>, Color3 = <rgb>, bool, object).
using Param = std::pair<std::string, Properties::Value>;

inline Properties make_props(const std::string& category, const std::string& type,
                             const std::vector<Param>& params) {
    Properties props(category, type, {"test.xml", 1});
    int line = 2;
    for (const auto& [name, value] : params) {
        std::string cat = "float";
        if (std::holds_alternative<std::string>(value)) cat = "string";
        if (std::holds_alternative<Color3>(value)) cat = "rgb";
        if (std::holds_alternative<bool>(value)) cat = "boolean";
        if (std::holds_alternative<ObjectPtr>(value)) cat = "bsdf";
        props.set(name, cat, value, {"test.xml", line++});
    }
    return props;
}

// Creates a BSDF like the loader does (factory, then every parameter must have been used).
inline std::shared_ptr<BSDF> make_bsdf(const std::string& type, const std::vector<Param>& params = {}) {
    Properties props = make_props("bsdf", type, params);
    ObjectPtr obj = create_bsdf(props);
    props.check_all_used();
    return std::dynamic_pointer_cast<BSDF>(obj);
}

inline SurfaceInteraction local_si(const Vec3f& wi) {
    SurfaceInteraction si;
    si.t = 1.f;
    si.n = Normal3f(0, 0, 1);
    si.wi = normalize(wi);
    si.uv = Vec2f(0.3f, 0.6f);
    return si;
}

// Direction with the given cos(theta) and azimuth phi.
inline Vec3f dir(float cos_theta, float phi = 0.4f) {
    float s = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
    return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// Runs the chi-square test of bsdf.sample() against bsdf.pdf(), including the weight check.
inline ChiSquareResult chi2_bsdf(const BSDF& bsdf, const SurfaceInteraction& si, const ChiSquareOptions& opt,
                                 TransportMode mode = TransportMode::Radiance) {
    BSDFContext ctx;
    ctx.mode = mode;
    auto sample = [&](Sampler& s) {
        float u1 = s.next_1d();
        Point2f u2 = s.next_2d();
        auto [bs, w] = bsdf.sample(ctx, si, u1, u2);
        ChiSquareSample r;
        r.d = bs.wo;
        r.weight = w;
        r.delta = (bs.sampled_flags & bsdf_flags::Delta) != 0;
        r.valid = bs.pdf > 0.f && !w.is_black();
        return r;
    };
    auto pdf = [&](const Vec3f& wo) { return double(bsdf.pdf(ctx, si, wo)); };
    auto eval = [&](const Vec3f& wo) { return bsdf.eval(ctx, si, wo); };
    return chi2_test_sphere(sample, pdf, opt, eval);
}

}  // namespace volguide::test
