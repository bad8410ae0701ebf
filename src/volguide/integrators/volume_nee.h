#pragma once
// Helpers shared by the volumetric integrators: the medium a ray enters at a surface, and
// next-event estimation whose shadow ray passes through null surfaces (null BSDF, the straight
// transmission of thindielectric) and accumulates the transmittance of every medium segment, as
// Mitsuba 3's volpath does.
#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/geometry/interaction.h"
#include "volguide/geometry/shape.h"

namespace volguide {

class Scene;
class Medium;

// How many null surfaces (null BSDF, thindielectric's straight transmission) one path may cross in
// all before it ends (counted over the whole path, not reset at real events), in every path loop (volpath's walk, simple_volpath, the
// photon pass's transport, the pixel estimate's camera rays): a ray that keeps re-hitting the
// surface it leaves, or caught between coincident null surfaces, would otherwise never end. Real
// scenes' paths cross far fewer, so the cap only ends such stuck rays.
constexpr int kMaxNullCrossings = 1024;

// Mitsuba's is_medium_transition(): the shape declares an interior or an exterior medium.
inline bool is_medium_transition(const Shape& shape) {
    return shape.interior_medium() != nullptr || shape.exterior_medium() != nullptr;
}

// The medium a ray leaving the surface `si` in world direction d travels in; a shape without
// media leaves the current medium unchanged.
inline const Medium* medium_after(const SurfaceInteraction& si, const Vec3f& d, const Medium* current) {
    if (!is_medium_transition(*si.shape)) return current;
    return si.shape->target_medium(si.n, d);
}

// A miss is represented as an invalid interaction whose wi is the world direction -ray.d.
inline SurfaceInteraction miss_interaction(const Ray& ray) {
    SurfaceInteraction si;
    si.t = Infinity;
    si.wi = -ray.d;
    return si;
}

// Transmittance from `ref` (travelling in `medium`, the medium on the side the shadow ray
// leaves through) to the emitter sample `ds`: the product of every medium segment's estimate and
// of eval_null_transmission() at every surface crossed; zero at an opaque surface.
Color3 shadow_transmittance(const Scene& scene, const Interaction& ref, const Medium* medium,
                            const DirectionSample& ds, Sampler& sampler);

struct VolumeEmitterSample {
    DirectionSample ds;
    Color3 weight{0.f};  // radiance / pdf (solid angle, choice included) * transmittance
};

// Next-event estimation from `ref`; for a surface reference pass the surface so the shadow ray
// starts in the medium on the side it leaves through (`medium` = the current ray medium).
VolumeEmitterSample sample_emitter_through_media(const Scene& scene, const Interaction& ref,
                                                 const SurfaceInteraction* ref_surface, const Medium* medium,
                                                 Point2f u, Sampler& sampler);

// Direction record of an emitter hit at `si` (or the environment when si is a miss) seen from
// `ref`, for the MIS pdf of emitter sampling.
DirectionSample emitter_hit_record(const SurfaceInteraction& si, const Interaction& ref, const Vec3f& ray_d,
                                   const class Emitter* emitter);

}  // namespace volguide
