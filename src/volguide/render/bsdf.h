#pragma once
// BSDF interface, in Mitsuba 3's convention: directions in the local shading frame (normal = +z),
// wi = si.wi points towards the previous vertex, eval() returns f(wi, wo) * |cos(theta_o)|, and
// sample() returns the weight eval/pdf (for delta lobes, the weight directly).
#include <cstdint>
#include <utility>

#include "volguide/core/color.h"
#include "volguide/core/object.h"
#include "volguide/geometry/interaction.h"

namespace volguide {

enum class TransportMode { Radiance, Importance };

namespace bsdf_flags {
enum : uint32_t {
    None = 0,
    Null = 1u << 0,  // index-matched pass-through (null BSDF)
    DiffuseReflection = 1u << 1,
    DiffuseTransmission = 1u << 2,
    GlossyReflection = 1u << 3,
    GlossyTransmission = 1u << 4,
    DeltaReflection = 1u << 5,
    DeltaTransmission = 1u << 6,
    Reflection = DiffuseReflection | GlossyReflection | DeltaReflection,
    Transmission = DiffuseTransmission | GlossyTransmission | DeltaTransmission | Null,
    Diffuse = DiffuseReflection | DiffuseTransmission,
    Glossy = GlossyReflection | GlossyTransmission,
    Delta = DeltaReflection | DeltaTransmission | Null,
    Smooth = Diffuse | Glossy,
    All = Null | Diffuse | Glossy | DeltaReflection | DeltaTransmission,
};
}

struct BSDFContext {
    TransportMode mode = TransportMode::Radiance;
};

struct BSDFSample {
    Vec3f wo;                     // local frame
    float pdf = 0.f;              // solid angle; for delta lobes the discrete probability of the lobe
    float eta = 1.f;              // relative IOR crossed (1 for reflection)
    uint32_t sampled_flags = 0;   // the one bsdf_flags lobe that was sampled
};

class BSDF : public Object {
public:
    // weight = f * |cos theta_o| / pdf; zero weight (and pdf 0) when sampling failed.
    virtual std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si,
                                                 float sample1, Point2f sample2) const = 0;
    // f * |cos theta_o| for the non-delta lobes; zero for delta lobes.
    virtual Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const = 0;
    // Solid-angle pdf of sample() producing wo through a non-delta lobe.
    virtual float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const = 0;
    // Mitsuba 3's eval_null_transmission(): the fraction of light passing straight through the
    // surface along -wi (the Null lobe). 1 for `null`, 1 - R' for `thindielectric`, 0 otherwise.
    // Shadow rays and transmittance estimation through surfaces multiply by it.
    virtual Color3 eval_null_transmission(const SurfaceInteraction& si) const { return Color3(0.f); }
    uint32_t flags() const { return flags_; }
    bool has(uint32_t f) const { return (flags_ & f) != 0; }
    bool is_null() const { return flags_ == bsdf_flags::Null; }

protected:
    uint32_t flags_ = 0;
};

}  // namespace volguide
