#pragma once
// Mitsuba's `homogeneous` medium: constant (possibly chromatic) sigma_t times `scale`, albedo a
// constant or a volume (Mitsuba allows a spatially varying albedo here), a phase function.
// Free flights are sampled in closed form with one-sample spectral MIS (docs/theory.md §2.6): a
// channel c is picked with probability P_c proportional to the path throughput,
// t ~ sigma_t,c exp(-sigma_t,c t), and every channel is weighted with the mixture pdf
// p(t) = sum_c P_c sigma_t,c exp(-sigma_t,c t)  (escape: P = sum_c P_c exp(-sigma_t,c tmax)).
// Transmittance is exact (media/homogeneous_transmittance.h). Its majorant walk is one segment.
#include "volguide/media/medium.h"
#include "volguide/media/volume.h"

namespace volguide {

class HomogeneousMedium final : public Medium {
public:
    // sigma_t already includes `scale`.
    HomogeneousMedium(const Color3& sigma_t, std::shared_ptr<Volume> albedo, std::shared_ptr<PhaseFunction> phase,
                      bool sample_emitters = true);

    MediumCoefficients eval(const Point3f& p) const override;
    // Closed form (one-sample spectral MIS, above).
    FreeFlightSample sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                        Sampler& sampler) const override;
    // One majorant segment (0, tmax) at the largest channel of sigma_t (walk_constant_majorant).
    void sample_majorant_walk(const Ray& ray, float tmax, Sampler& sampler, MajorantCallback collide) const override;
    Color3 albedo(const Point3f& p) const override { return albedo_at(p); }
    bool tracks_null_collisions() const override { return false; }
    Color3 transmittance(const Ray& ray, float tmax, Sampler& sampler) const override;
    void proxy_segments(const Ray& ray, float t0, float t1, std::vector<ProxySegment>& out) const override;
    bool constant_proxy(ProxySegment& proxy) const override;
    bool is_homogeneous() const override { return true; }
    BBox3f bbox() const override;
    const Color3& sigma_t() const { return sigma_t_; }
    std::string to_string() const override;

private:
    Color3 albedo_at(const Point3f& p) const { return albedo_const_ ? albedo_value_ : albedo_->eval(p); }

    Color3 sigma_t_;
    std::shared_ptr<Volume> albedo_;
    bool albedo_const_;
    Color3 albedo_value_;
    bool grey_;  // all channels of sigma_t equal: the MIS weights reduce to 1 and the albedo
};

std::shared_ptr<Medium> make_homogeneous_medium(const Properties& props);

}  // namespace volguide
