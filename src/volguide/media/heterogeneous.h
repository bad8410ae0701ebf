#pragma once
// Mitsuba's `heterogeneous` medium: sigma_t (a volume, or a constant, which Mitsuba turns into a
// constvolume over the unit cube) times `scale`, albedo (constant or volume), a phase function.
// The medium exists inside the sigma_t volume's box (Mitsuba: intersect_aabb of sigma_t).
//
// Free flights: one null-collision walk over a majorant grid with a 3-D DDA (tentative collisions at
// each cell's rate mu), whose scatter/continue decisions come from a policy (media/collision_policy.h):
// spectral tracking (Kutz et al. 2017) by default, at a tentative collision with tracking weight w
// a real collision with probability
//   P_c = <|sigma_t w|> / (<|sigma_t w|> + <|sigma_n w|>),  sigma_n = mu - sigma_t,
// (<.> = channel average) and the weight becomes w sigma_s / (mu P_c) (absorption is folded
// into the weight: real collisions always scatter); a null collision has P_n = 1 - P_c and
// w <- w sigma_n / (mu P_n). For grey sigma_t this is delta tracking with weight = albedo.
// With absolute values the estimator stays unbiased even where mu < sigma_t (only noisier).
// The walk is also handed to callers (sample_majorant_walk): guided tracking (media/majorant_tracking.h)
// is the same walk with the caller's scatter probability.
// Transmittance: ratio tracking, or residual ratio tracking with the per-cell per-channel mean
// as control (default); both unbiased for any majorant. Both stop small estimates by unbiased
// Russian roulette (survival max|T| / 0.05 once max|T| < 0.05).
#include <cmath>

#include "volguide/media/dda.h"
#include "volguide/media/majorant_grid.h"
#include "volguide/media/medium.h"
#include "volguide/media/volume.h"

namespace volguide {

enum class TransmittanceEstimator { Ratio, ResidualRatio };

class HeterogeneousMedium final : public Medium {
public:
    HeterogeneousMedium(std::shared_ptr<Volume> sigma_t, float scale, std::shared_ptr<Volume> albedo,
                        std::shared_ptr<PhaseFunction> phase, bool sample_emitters = true);

    // Tests and benchmarks: multiply every majorant (and residual rate) by `factor` > 0. A
    // looser majorant (factor > 1) only costs time; the estimators stay unbiased.
    void set_majorant_scale(float factor) { majorant_scale_ = factor; }
    void set_transmittance_estimator(TransmittanceEstimator e) { estimator_ = e; }

    MediumCoefficients eval(const Point3f& p) const override;
    FreeFlightSample sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                        Sampler& sampler) const override {
        return sample_free_flight(ray, tmax, throughput, sampler, nullptr);
    }
    // The same with event counters (optional): real = the scatter, null = the other collisions.
    FreeFlightSample sample_free_flight(const Ray& ray, float tmax, const Color3& throughput, Sampler& sampler,
                                        TrackingCounts* counts) const;
    // The walk of for_each_tentative_collision below, handed to the caller (one indirect call per
    // collision; the medium's own estimators use the walk inlined).
    void sample_majorant_walk(const Ray& ray, float tmax, Sampler& sampler, MajorantCallback collide) const override;
    Color3 albedo(const Point3f& p) const override { return albedo_->eval(p); }
    bool tracks_null_collisions() const override { return true; }
    Color3 transmittance(const Ray& ray, float tmax, Sampler& sampler) const override;
    void proxy_segments(const Ray& ray, float t0, float t1, std::vector<ProxySegment>& out) const override;
    Color3 ratio_tracking(const Ray& ray, float tmax, Sampler& sampler) const;
    Color3 residual_ratio_tracking(const Ray& ray, float tmax, Sampler& sampler) const;
    bool is_homogeneous() const override { return false; }
    BBox3f bbox() const override { return sigma_t_->bbox(); }
    const MajorantGrid& majorants() const { return majorants_; }
    std::string to_string() const override;

private:
    // The tentative collisions of the free flight and of ratio tracking along the local segment o + t d,
    // t in (t0, t1): a Poisson process at each majorant cell's rate mu, walked cell by cell with a
    // DDA. Calls collide(t, mu) at each; it returns false to stop. The optical depth to the next
    // collision is redrawn (one random number) after each collision that continues.
    template <class Collide>
    void for_each_tentative_collision(const Point3f& o, const Vec3f& d, float t0, float t1, Sampler& sampler,
                                      TrackingCounts* counts, Collide&& collide) const {
        const int* res = majorants_.res();
        const Vec3f cells{float(res[0]), float(res[1]), float(res[2])};
        float tau = -std::log1p(-sampler.next_1d());  // optical depth (majorant units) to the next collision
        for (GridDda dda(o * cells, d * cells, res, t0, t1); !dda.done(); dda.advance()) {
            if (counts) ++counts->cells;
            const float mu = majorant_scale_ * majorants_.cell(dda.cell(0), dda.cell(1), dda.cell(2)).majorant;
            const float seg_end = dda.segment_end();
            float t = dda.t();
            if (!(mu > 0.f)) continue;
            while (true) {
                const float dt = tau / mu;
                if (t + dt >= seg_end) {
                    tau -= (seg_end - t) * mu;
                    break;
                }
                t += dt;
                if (!collide(t, mu)) return;
                tau = -std::log1p(-sampler.next_1d());
            }
        }
    }

    // The ray in the sigma_t volume's local coordinates (t unchanged) clipped to the unit cube
    // and (0, tmax); false when it misses.
    bool local_segment(const Ray& ray, float tmax, Point3f& o, Vec3f& d, float& t0, float& t1) const;
    Color3 sigma_t_local(const Point3f& u) const { return sigma_t_->grid().lookup(u) * scale_; }

    std::shared_ptr<Volume> sigma_t_, albedo_;
    float scale_;
    MajorantGrid majorants_;
    float majorant_scale_ = 1.f;
    TransmittanceEstimator estimator_ = TransmittanceEstimator::ResidualRatio;
};

std::shared_ptr<Medium> make_heterogeneous_medium(const Properties& props);

}  // namespace volguide
