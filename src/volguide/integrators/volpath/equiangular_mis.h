#pragma once
// Equiangular sampling in volpath's walk (setting `equiangular`), homogeneous media only. Per medium
// segment [0, tmax] of the ray o + t d, the direct light scattered once on the segment is the
// integral over (t, y), y a point on a light (for point/spot lights y is fixed), estimated by three
// strategies:
//   1. distance sampling t ~ p_d, then NEE y ~ p_nee(y | x_t)        density p1 = p_d(t) p_nee(y | x_t)
//   2. distance sampling, then phase sampling hits y (area lights)   density p2 = p_d(t) p_phase G
//   3. equiangular: y ~ p_E(y) (light sampled from o), t ~ p_e(t | y)  density p3 = p_E(y) p_e(t | y)
// with light densities in y's measure (area for area lights, the choice probability for delta
// lights) and G = |cos_y| / dist^2 converting the phase pdf. Each strategy is weighted by the power
// heuristic over all three, so the weights sum to one for every (t, y): unbiased. The distance
// sampler must expose its density for this, so in these segments the walk samples the distance
// itself (homogeneous: one channel chosen in proportion to the throughput, mixture density over
// the channels, docs/theory.md §2.6) instead of calling Medium::sample_free_flight. In heterogeneous
// media the walk keeps plain free-flight sampling (volpath's preprocess warns): the tracking's
// density is not available in closed form there.
#include <optional>

#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/geometry/interaction.h"
#include "volguide/geometry/shape.h"
#include "volguide/media/medium.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

class Emitter;
class Scene;

// The segment of a homogeneous medium on which equiangular sampling runs, with the channel
// probabilities its distance sampling uses.
struct EquiSegment {
    Point3f o;
    Vec3f d;
    float tmax = 0.f;
    Color3 sigma_t, sigma_s;
    Color3 channel_probs{1.f / 3.f};
    float distance_pdf(float t) const { return spectral_distance_pdf(sigma_t, channel_probs, t); }
};

// A medium vertex sampled by strategy 1's distance sampling on `seg` (on = false: any other
// vertex), kept for the MIS of its NEE and of the emitter its continuation hits.
struct EquiVertex {
    bool on = false;
    EquiSegment seg;
    float t = 0.f;   // the vertex's distance on the segment
    float pd = 0.f;  // the distance density there
};

// Emitters equiangular sampling can aim at: point, spot (a position) and area lights.
bool equiangular_target(const Emitter* e);

// The segment of `medium` (homogeneous, coefficients mc) along ray up to tmax, for a path of
// weight `throughput`.
EquiSegment equiangular_segment(const Ray& ray, float tmax, const MediumCoefficients& mc, const Color3& throughput);

// Strategy 3 on the segment for a path of weight `throughput` (draws 3 numbers, and the shadow
// ray's): its MIS-weighted contribution, nothing when it has none.
std::optional<Color3> equiangular_light_sample(const Scene& scene, const Medium& medium, const EquiSegment& seg,
                                               const Color3& throughput, Sampler& sampler);

// Strategies 1 and 2's distance sampling on the segment (one number): weight and, when it
// scattered, the vertex (mi with coefficients mc) and its EquiVertex.
FreeFlightSample equiangular_free_flight(const Ray& ray, const EquiSegment& seg, const MediumCoefficients& mc,
                                         const Medium* medium, Sampler& sampler, EquiVertex& vertex);

// Whether the three-way weights apply to the light sample or emitter hit `ds` at the vertex v.
bool equiangular_mis_applies(const EquiVertex& v, const DirectionSample& ds);
// Strategy 1's weight for NEE's light sample ds at the vertex x (pp: the direction decision's pdf).
float equiangular_nee_weight(const Scene& scene, const Interaction& x, const EquiVertex& v,
                             const DirectionSample& ds, float pp);
// Strategy 2's weight for an emitter hit ds (record from the vertex) by the direction sampled with
// density last_pdf, emitter sampling's density being emitter_pdf.
float equiangular_hit_weight(const Scene& scene, const EquiVertex& v, const DirectionSample& ds, float last_pdf,
                             float emitter_pdf);

}  // namespace volguide
