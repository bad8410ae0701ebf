#pragma once
// A nested BSDF evaluated in a perturbed shading frame (bumpmap, normalmap), as Mitsuba 3 (since its
// "improved bump and normal mapping", which made the suite's references): the subclass gives the
// perturbed normal and a tangent direction relative to the surface's shading frame; here, once:
// - `flip_invalid_normals` (default true): a perturbed normal that puts wi on its other side than the
//   shading normal does is mirrored about the shading normal, (x, y, z) -> (-x, -y, z) (Schüssler et
//   al. 2017's remedy);
// - the frame: that normal, the tangent made orthogonal to it (Gram-Schmidt);
// - wi and wo carried into it; a direction on opposite sides of the two frames' surfaces gives zero;
// - `use_shadowing_function` (default true): the value (not the pdf) times Estevez et al.'s microfacet
//   shadowing term G = 2 / (1 + sqrt(1 + a² tan²θ_o)), a² = min(tan²θ_n / 8, 1) (docs/theory.md §20).
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "volguide/core/frame.h"
#include "volguide/core/properties.h"
#include "volguide/render/bsdf.h"

namespace volguide {

class ShadingFrameBSDF : public BSDF {
  public:
    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const final {
        const Frame lf = local_frame(si);
        auto [bs, weight] = nested_->sample(ctx, perturbed(si, lf), sample1, sample2);
        if (weight.is_black()) return {bs, weight};
        const Vec3f wo = lf.to_world(bs.wo);
        if (!(bs.wo.z * wo.z > 0.f)) return {BSDFSample{}, Color3(0.f)};
        bs.wo = wo;
        return {bs, weight * shadowing(lf.n, wo)};
    }
    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const final {
        const Frame lf = local_frame(si);
        const Vec3f pwo = lf.to_local(wo);
        if (!(wo.z * pwo.z > 0.f)) return Color3(0.f);
        return nested_->eval(ctx, perturbed(si, lf), pwo) * shadowing(lf.n, wo);
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const final {
        const Frame lf = local_frame(si);
        const Vec3f pwo = lf.to_local(wo);
        if (!(wo.z * pwo.z > 0.f)) return 0.f;
        return nested_->pdf(ctx, perturbed(si, lf), pwo);
    }

    // Estevez et al. 2019's shadowing term for a perturbed normal n and a direction wo, both relative
    // to the unperturbed shading frame (docs/theory.md §20).
    static float shadow_terminator(const Vec3f& n, const Vec3f& wo) {
        const float a2 = std::min(0.125f * Frame::tan_theta_2(n), 1.f);
        if (a2 == 0.f) return 1.f;
        return 2.f / (1.f + std::sqrt(1.f + a2 * Frame::tan_theta_2(wo)));
    }

  protected:
    // The two switches Mitsuba 3's bumpmap and normalmap share (both default true).
    explicit ShadingFrameBSDF(const Properties& props)
        : flip_invalid_normals_(props.get_bool("flip_invalid_normals", true)),
          use_shadowing_function_(props.get_bool("use_shadowing_function", true)) {}

    // The perturbed normal relative to si's shading frame (need not be unit length).
    virtual Vec3f local_normal(const SurfaceInteraction& si) const = 0;
    // The direction the perturbed frame's tangent is made from, relative to si's shading frame.
    virtual Vec3f local_tangent(const SurfaceInteraction& si) const = 0;

    std::shared_ptr<BSDF> nested_;

  private:
    // The perturbed frame relative to si's shading frame.
    Frame local_frame(const SurfaceInteraction& si) const {
        Vec3f n = local_normal(si);
        if (flip_invalid_normals_ && si.wi.z * dot(si.wi, n) <= 0.f) n = Vec3f(-n.x, -n.y, n.z);
        Frame f;
        f.n = normalize(n);
        const Vec3f hint = local_tangent(si);
        f.s = normalize(hint - f.n * dot(f.n, hint));
        f.t = cross(f.n, f.s);
        return f;
    }
    // si with its shading frame replaced by lf (carried to world space) and wi carried into it.
    static SurfaceInteraction perturbed(const SurfaceInteraction& si, const Frame& lf) {
        SurfaceInteraction out(si);
        out.sh_frame = Frame(si.to_world(lf.s), si.to_world(lf.t), si.to_world(lf.n));
        out.wi = lf.to_local(si.wi);
        return out;
    }
    float shadowing(const Vec3f& n, const Vec3f& wo) const {
        return use_shadowing_function_ ? shadow_terminator(n, wo) : 1.f;
    }

    bool flip_invalid_normals_;
    bool use_shadowing_function_;
};

}  // namespace volguide
