#pragma once
// What the guiding field predicts a camera sees through the media (issue 6's `estimate` mode and,
// later, the ray-marched pixel estimate of guided RR and splitting, docs/theory.md §9.5, eq. 9.2 without
// the surface term): along the camera ray, through every medium and across null (index-matched)
// surfaces up to the first real surface,
//   inscattered:  integral of T(0, t) sigma_s(x_t) L~_i(x_t, d) dt
//   incident:     integral of T(0, t) sigma_s(x_t) L~(x_t, d) dt
// with d the ray direction. The first is the field's estimate of the "V" image (volpath's
// volume_only); the second replaces the phase function by a forward delta — the incident radiance
// from straight ahead, the quantity directional guiding reads.
//
// The march follows the kd-tree leaves (the field is piecewise constant in space): a homogeneous
// medium integrates each leaf interval in closed form, a heterogeneous one in sub-steps of at most
// 1/`steps_per_diagonal` of its bounding box's diagonal (about half a voxel for the benchmark
// cloud), with sigma at a jittered point of each step. An estimate, not an unbiased one: it shapes
// probabilities and inspection images, never weights.
#include <map>
#include <memory>

#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/inscatter_cache.h"

namespace volguide {

class Scene;
class Medium;

enum class CacheQuantity { Inscattered, Incident };

class CacheEstimator {
public:
    // Prepares one InscatterCache per distinct phase mean cosine among the scene's media. The field
    // and the scene must outlive the estimator.
    CacheEstimator(const Scene& scene, const GuidingField& field);

    Color3 estimate(const Ray& camera_ray, const Medium* camera_medium, CacheQuantity quantity,
                    Sampler& sampler) const;
    // A stretch of a ray inside one medium: ray(t), t in (t0, t1).
    struct Segment {
        const Ray& ray;
        float t0, t1;
        const Medium& medium;
    };
    // Adds the integral over `segment` to `result` and attenuates the transmittance T along it (the
    // pixel estimate marches its own paths with it).
    void march_segment(const Segment& segment, CacheQuantity quantity, Sampler& sampler, Color3& transmittance,
                       Color3& result) const;
    const Scene& scene() const { return scene_; }
    const GuidingField& field() const { return field_; }

    int steps_per_diagonal = 128;
    int max_null_crossings = 64;

private:
    // L~_i or L~ of leaf `leaf` for direction d in `medium`.
    Color3 leaf_value(int leaf, const Vec3f& d, const Medium& medium, CacheQuantity quantity) const;

    const Scene& scene_;
    const GuidingField& field_;
    std::map<float, InscatterCache> inscatter_;  // by phase mean cosine
};

}  // namespace volguide
