#include "volguide/integrators/openpgl/openpgl_vsp_distance.h"

#include "volguide/integrators/guided/walk/vsp_distance.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

namespace {

// Homogeneous media: the closed-form decision (HomogeneousVsp), three random numbers per segment.
FreeFlightSample openpgl_vsp_homogeneous(const DistanceQuery& query, float vsp, float c, Sampler& sampler) {
    const Medium& medium = query.medium;
    const Ray& ray = query.ray;
    const HomogeneousVsp segment(medium.eval(ray.o).sigma_t, query.tmax, channel_probabilities(query.throughput));
    const float P = segment.probability(vsp, c);
    const float u_decide = sampler.next_1d(), u_channel = sampler.next_1d(), u_t = sampler.next_1d();
    const HomogeneousVsp::Sample vs = segment.sample(P, u_decide, u_channel, u_t);
    FreeFlightSample fs;
    fs.t = vs.t;
    fs.weight = fs.flight_weight = vs.flight_weight;
    if (vs.scattered) {
        const Point3f p = ray(vs.t);
        fs.scatter_at(ray, vs.t, p, &medium, medium.eval(p));
        fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
    }
    return fs;
}

}  // namespace

FreeFlightSample openpgl_vsp_flight(const DistanceQuery& query, float vsp, float c, Sampler& sampler) {
    if (query.medium.is_homogeneous()) return openpgl_vsp_homogeneous(query, vsp, c, sampler);
    // Any other medium: the unguided probability is the resampling's estimate of it.
    auto probability = [vsp, c](float unguided) { return c * unguided + (1.f - c) * vsp; };
    return resampled_segment_flight(query.medium, query.ray, query.tmax, query.throughput, probability, sampler);
}

}  // namespace volguide
