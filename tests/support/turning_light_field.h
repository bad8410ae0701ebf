#pragma once
// A fitted guiding field over the box [0, 2] x [0, 1] x [0, 1] for the leaf-table and leaf-group
// tests: radiance from a direction that turns with x (angle `turn` * x about +z, lifted by 0.3), a
// vMF lobe of concentration `kappa` holding 70 % of it plus a uniform part, RGB weight (2, 1, 0.5),
// 20000 samples; every leaf differs a little from its neighbours, as fitted leaves do.
#include <cmath>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/guiding_field.h"

namespace volguide::test {

inline const BBox3f kTurningLightBox(Point3f(0.f), Point3f(2.f, 1.f, 1.f));

inline GuidingField turning_light_field(float kappa, float turn, int leaf_samples, int lobes) {
    std::vector<RadianceSample> out;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(11, 0, uint64_t(i));
        const Point3f p(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const VmfLobe lobe(normalize(Vec3f(std::cos(turn * p.x), std::sin(turn * p.x), 0.3f)), kappa);
        const Vec3f d = s.next_1d() < 0.7f ? lobe.sample(s.next_2d()) : warp::square_to_uniform_sphere(s.next_2d());
        out.push_back({p, d, Color3(2.f, 1.f, 0.5f)});
    }
    GuidingFieldSettings settings;
    settings.tree.max_samples = leaf_samples;
    settings.lobes = lobes;
    return GuidingField::build(kTurningLightBox, out, settings);
}

}  // namespace volguide::test
