#include "volguide/media/homogeneous.h"

#include <fmt/format.h>

#include "volguide/media/homogeneous_transmittance.h"
#include "volguide/media/medium_params.h"
#include "volguide/media/spectral_mis.h"

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

void HomogeneousMedium::proxy_segments(const Ray& ray, float t0, float t1, std::vector<ProxySegment>& out) const {
    if (!(t0 < t1)) return;
    // sigma_t is exact; a textured albedo is read at the segment's middle (probabilities only).
    const float st = sigma_t_.average();
    const float albedo = st > 0.f ? (sigma_t_ * albedo_at(ray(0.5f * (t0 + t1)))).average() / st : 0.f;
    out.push_back({t0, t1, sigma_t_, albedo});
}

bool HomogeneousMedium::constant_proxy(ProxySegment& proxy) const {
    if (!albedo_const_) return false;
    const float st = sigma_t_.average();  // as proxy_segments, with the albedo everywhere the same
    proxy = {0.f, 0.f, sigma_t_, st > 0.f ? (sigma_t_ * albedo_value_).average() / st : 0.f};
    return true;
}

void HomogeneousMedium::sample_majorant_walk(const Ray&, float tmax, Sampler& sampler, MajorantCallback collide) const {
    walk_constant_majorant(sigma_t_, tmax, sampler, collide);
}

FreeFlightSample HomogeneousMedium::sample_free_flight(const Ray& ray, float tmax, const Color3& throughput,
                                                       Sampler& sampler) const {
    float u_channel = sampler.next_1d();
    const float u_t = sampler.next_1d();
    const Color3 probs = grey_ ? Color3(1.f / 3.f) : channel_probabilities(throughput);
    const int c = sample_channel(probs, u_channel);
    const float sigma_c = sigma_t_[c];
    const float t = sigma_c > 0.f ? -std::log1p(-u_t) / sigma_c : Infinity;

    FreeFlightSample fs;
    if (t < tmax) {
        const Point3f p = ray(t);
        fs.scatter_at(ray, t, p, this, {sigma_t_, sigma_t_ * albedo_at(p)});
        if (grey_) {
            fs.flight_weight = Color3(1.f / sigma_t_.r);
        } else {
            const float pdf = spectral_distance_pdf(sigma_t_, probs, t);
            fs.flight_weight = pdf > 0.f ? transmittance_rgb(sigma_t_, t) / pdf : Color3(0.f);
        }
        fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
    } else {
        fs.scattered = false;
        fs.t = tmax;
        if (!grey_) {
            const float prob = spectral_escape_probability(sigma_t_, probs, tmax);
            fs.weight = prob > 0.f ? transmittance_rgb(sigma_t_, tmax) / prob : Color3(0.f);
        }
        fs.flight_weight = fs.weight;
    }
    return fs;
}

Color3 HomogeneousMedium::transmittance(const Ray&, float tmax, Sampler&) const {
    return transmittance_rgb(sigma_t_, tmax);
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
    // Mitsuba 3's flag only tells its volpath that the extinction is the same in every channel (it then
    // skips the spectral reweighting); volguide always weights spectrally, which gives the same image
    // when the extinction is gray. A chromatic extinction with the flag off renders something else in
    // Mitsuba (one channel's free flights, unweighted), which volguide does not reproduce.
    if (!props.get_bool("has_spectral_extinction", true) && !(sigma_t.r == sigma_t.g && sigma_t.g == sigma_t.b))
        props.fail_at("has_spectral_extinction",
                      "homogeneous: has_spectral_extinction=false needs a gray sigma_t (got {} {} {}): Mitsuba 3 "
                      "then samples one channel's extinction without spectral weights, which volguide does not reproduce",
                      sigma_t.r, sigma_t.g, sigma_t.b);
    return std::make_shared<HomogeneousMedium>(sigma_t, mp.albedo, mp.phase, mp.sample_emitters);
}

}  // namespace volguide
