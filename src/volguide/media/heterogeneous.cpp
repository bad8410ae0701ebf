#include "volguide/media/heterogeneous.h"

#include <algorithm>

#include "volguide/media/dda.h"

#include <fmt/format.h>

#include "volguide/media/medium_params.h"

namespace volguide {

HeterogeneousMedium::HeterogeneousMedium(std::shared_ptr<Volume> sigma_t, float scale, std::shared_ptr<Volume> albedo,
                                         std::shared_ptr<PhaseFunction> phase, bool sample_emitters)
    : sigma_t_(std::move(sigma_t)), albedo_(std::move(albedo)), scale_(scale), majorants_(sigma_t_->grid(), scale) {
    phase_ = std::move(phase);
    sample_emitters_ = sample_emitters;
}

MediumCoefficients HeterogeneousMedium::eval(const Point3f& p) const {
    const Point3f u = sigma_t_->to_local().point(p);
    if (!(u.x >= 0.f && u.x <= 1.f && u.y >= 0.f && u.y <= 1.f && u.z >= 0.f && u.z <= 1.f))
        return {Color3(0.f), Color3(0.f)};
    const Color3 st = sigma_t_local(u);
    return {st, st * albedo_->eval(p)};
}

bool HeterogeneousMedium::local_segment(const Ray& ray, float tmax, Point3f& o, Vec3f& d, float& t0,
                                        float& t1) const {
    o = sigma_t_->to_local().point(ray.o);
    d = sigma_t_->to_local().vector(ray.d);
    t0 = 0.f;
    t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.f) {
            if (o[a] < 0.f || o[a] > 1.f) return false;
            continue;
        }
        const float inv = 1.f / d[a];
        float ta = (0.f - o[a]) * inv, tb = (1.f - o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 < t1;
}

void HeterogeneousMedium::proxy_segments(const Ray& ray, float t0, float t1, std::vector<ProxySegment>& out) const {
    if (!(t0 < t1)) return;
    Point3f o;
    Vec3f d;
    float g0, g1;  // the part of (0, t1) inside the grid
    auto zero = [&](float a, float b) {
        if (a < b) out.push_back({a, b, Color3(0.f), 0.f});
    };
    if (!local_segment(ray, t1, o, d, g0, g1) || g1 <= t0) return zero(t0, t1);
    g0 = std::max(g0, t0);
    zero(t0, g0);
    const int* res = majorants_.res();
    const Vec3f cells{float(res[0]), float(res[1]), float(res[2])};
    float t = g0;
    for (GridDda dda(o * cells, d * cells, res, g0, g1); !dda.done(); dda.advance()) {
        const float end = std::min(dda.segment_end(), g1);
        if (!(end > t)) continue;
        const MajorantCell& cell = majorants_.cell(dda.cell(0), dda.cell(1), dda.cell(2));
        // Cell mean extinction; the albedo is read at the stretch's middle.
        const float st = cell.control.average();
        const float albedo = st > 0.f ? std::clamp(albedo_->eval(ray(0.5f * (t + end))).average(), 0.f, 1.f) : 0.f;
        out.push_back({t, end, cell.control, albedo});
        t = end;
    }
    // Float round-off in the DDA must not leave a gap: the segments tile (t0, t1) exactly.
    if (t < g1) {
        if (!out.empty() && out.back().t1 == t && out.back().sigma_t.max_value() > 0.f) out.back().t1 = g1;
        else zero(t, g1);
    }
    zero(g1, t1);
}

std::string HeterogeneousMedium::to_string() const {
    return fmt::format("HeterogeneousMedium[scale = {}, sigma_t = {}, max majorant = {}]", scale_,
                       sigma_t_->to_string(), majorants_.max_majorant());
}

std::shared_ptr<Medium> make_heterogeneous_medium(const Properties& props) {
    MediumParams mp = read_medium_params(props);
    return std::make_shared<HeterogeneousMedium>(mp.sigma_t, mp.scale, mp.albedo, mp.phase, mp.sample_emitters);
}

}  // namespace volguide
