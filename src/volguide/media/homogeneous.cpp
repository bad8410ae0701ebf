#include "volguide/media/homogeneous.h"

#include <fmt/format.h>

#include "volguide/media/medium_params.h"

namespace volguide {

HomogeneousMedium::HomogeneousMedium(const Color3& sigma_t, std::shared_ptr<Volume> albedo,
                                     std::shared_ptr<PhaseFunction> phase, bool sample_emitters)
    : sigma_t_(sigma_t), albedo_(std::move(albedo)) {
    phase_ = std::move(phase);
    sample_emitters_ = sample_emitters;
    albedo_const_ = albedo_->is_constant();
    albedo_value_ = albedo_->grid().lookup(Point3f(0.5f));
    grey_ = sigma_t.r == sigma_t.g && sigma_t.g == sigma_t.b;
}

MediumCoefficients HomogeneousMedium::eval(const Point3f& p) const { return {sigma_t_, sigma_t_ * albedo_at(p)}; }

// exp(-sigma t) with exp(-0 * inf) = 1.
static inline float transmittance_1(float sigma, float t) { return sigma > 0.f ? std::exp(-sigma * t) : 1.f; }

FreeFlightSample HomogeneousMedium::sample_free_flight(const Ray& ray, float tmax, Sampler& sampler) const {
    const float u_channel = sampler.next_1d(), u_t = sampler.next_1d();
    const int c = std::min(int(u_channel * 3.f), 2);
    const float sigma_c = sigma_t_[c];
    const float t = sigma_c > 0.f ? -std::log1p(-u_t) / sigma_c : Infinity;

    FreeFlightSample fs;
    if (t < tmax) {
        fs.scattered = true;
        fs.t = t;
        MediumInteraction& mi = fs.mi;
        mi.p = ray(t);
        mi.t = t;
        mi.wi = -ray.d;
        mi.medium = this;
        mi.coeffs = {sigma_t_, sigma_t_ * albedo_at(mi.p)};
        if (grey_) {
            fs.weight = mi.coeffs.sigma_s / sigma_t_;
        } else {
            const Color3 tr(transmittance_1(sigma_t_.r, t), transmittance_1(sigma_t_.g, t),
                            transmittance_1(sigma_t_.b, t));
            const float pdf = (sigma_t_ * tr).average();
            fs.weight = pdf > 0.f ? tr * mi.coeffs.sigma_s / pdf : Color3(0.f);
        }
    } else {
        fs.scattered = false;
        fs.t = tmax;
        if (!grey_) {
            const Color3 tr(transmittance_1(sigma_t_.r, tmax), transmittance_1(sigma_t_.g, tmax),
                            transmittance_1(sigma_t_.b, tmax));
            const float prob = tr.average();
            fs.weight = prob > 0.f ? tr / prob : Color3(0.f);
        }
    }
    return fs;
}

Color3 HomogeneousMedium::transmittance(const Ray&, float tmax, Sampler&) const {
    return {transmittance_1(sigma_t_.r, tmax), transmittance_1(sigma_t_.g, tmax), transmittance_1(sigma_t_.b, tmax)};
}

BBox3f HomogeneousMedium::bbox() const {
    return BBox3f(Point3f(-Infinity, -Infinity, -Infinity), Point3f(Infinity, Infinity, Infinity));
}

std::string HomogeneousMedium::to_string() const {
    return fmt::format("HomogeneousMedium[sigma_t = ({}, {}, {})]", sigma_t_.r, sigma_t_.g, sigma_t_.b);
}

std::shared_ptr<Medium> make_homogeneous_medium(const Properties& props) {
    MediumParams mp = read_medium_params(props);
    if (!mp.sigma_t->is_constant())
        props.fail_at("sigma_t", "homogeneous: sigma_t must be constant (use a heterogeneous medium for a grid)");
    const Color3 sigma_t = mp.sigma_t->grid().lookup(Point3f(0.5f)) * mp.scale;
    return std::make_shared<HomogeneousMedium>(sigma_t, mp.albedo, mp.phase, mp.sample_emitters);
}

}  // namespace volguide
