#include "volguide/integrators/guided/estimates/pixel_estimate.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "volguide/core/parallel.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/surface_guide.h"
#include "volguide/vmm/vmm.h"
#include "volguide/integrators/guided/estimates/cache_estimate.h"
#include "volguide/integrators/guided/estimates/surface_leaf.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

// The estimates' random streams, apart from camera paths (0) and training passes.
constexpr uint64_t kPixelEstimateStream = 0x9e57;

// Irradiance on a surface of normal n per unit fluence of a leaf whose incident radiance has the
// shape V: integral of V(w) max(0, n . w) dw, the clamped cosine replaced by pi times the vMF of
// mean cosine 2/3 on n (the same integral), so each lobe is a closed-form convolution (eq. 3.4).
float field_irradiance_shape(const Vmm& v, const Vec3f& n) {
    ZonalMixture<1> cosine;
    cosine.count = 1;
    cosine.weight[0] = 1.f;
    cosine.kappa[0] = cosine_lobe_kappa();
    cosine.sign[0] = 1.f;
    return float(Pi * convolve_exact(v, cosine, n));
}

// The estimated radiance along one camera ray (see pixel_estimate.h). `camera_segment`: the channel
// average of what the first medium segment before any real surface event scatters toward the camera
// (the march's T sigma_s L~_i over it), in .r, and 1 in .g when the ray has such a segment.
Color3 march_camera_ray(const CacheEstimator& estimator, const PixelEstimateSettings& settings, Ray ray,
                        Sampler& sampler, Color3& camera_segment) {
    const Scene& scene = estimator.scene();
    const GuidingField& field = estimator.field();
    const BSDFContext ctx;
    Color3 T(1.f), result(0.f);
    const Medium* medium = scene.sensor().medium();
    bool from_camera = true;  // no real surface event yet
    int null_crossings = 0;
    for (int event = 0; event <= settings.max_specular_events;) {
        SurfaceInteraction si;
        const bool hit = scene.intersect(ray, si);
        if (!hit) si = miss_interaction(ray);
        const float before = result.average();
        if (medium)
            estimator.march_segment({ray, 0.f, hit ? si.t : ray.tmax, *medium}, CacheQuantity::Inscattered, sampler, T,
                                    result);
        if (medium && from_camera && camera_segment.g == 0.f) camera_segment = Color3(result.average() - before, 1.f, 0.f);
        if (!(T.max_value() > 1e-7f)) break;
        const bool emission_counts = !settings.volume_only && !(from_camera && settings.hide_emitters);
        const Emitter* emitter = hit ? si.shape->emitter() : scene.environment();
        if (emitter && emission_counts) result += T * emitter->eval(si);
        if (!hit) break;
        const BSDF& bsdf = *si.shape->bsdf();
        if (bsdf.is_null()) {
            if (++null_crossings > kMaxNullCrossings) break;
            medium = medium_after(si, ray.d, medium);
            ray = si.spawn_ray(ray.d);
            continue;
        }
        if (settings.volume_only) break;  // the V image ends at the first real surface
        ++event;
        from_camera = false;
        if (!bsdf.has(bsdf_flags::Smooth)) {  // purely specular: follow one sampled lobe
            const float u1 = sampler.next_1d();
            const auto [bs, weight] = bsdf.sample(ctx, si, u1, sampler.next_2d());
            if (weight.is_black()) break;
            T *= weight;
            const Vec3f wo = si.to_world(bs.wo);
            medium = medium_after(si, wo, medium);
            ray = si.spawn_ray(wo);
            continue;
        }
        // A rough surface, seen from the side the ray arrives on: its albedo (one BSDF sample's
        // weight) times the irradiance there over pi, the irradiance from the field's leaf on that
        // side (both direct and indirect light, in closed form) or, without a valid leaf, from one
        // NEE sample (direct light only). Only a leaf that is mostly medium describes the light
        // around the surface (GuidingLeaf::mostly_medium; sss: the floor read black, I's mean well
        // below the image's; bench/RESULTS.md (issue 35)).
        const float u1 = sampler.next_1d();
        const Color3 albedo = bsdf.sample(ctx, si, u1, sampler.next_2d()).second;
        if (albedo.is_black()) break;
        const auto [n, index] = surface_leaf(field, si);
        const GuidingLeaf* leaf = index >= 0 ? &field.leaves()[size_t(index)] : nullptr;
        if (leaf && leaf->valid && leaf->mostly_medium()) {
            result += T * albedo * leaf->fluence * (field_irradiance_shape(leaf->vmm, n) * InvPi);
        } else {
            const VolumeEmitterSample es =
                sample_emitter_through_media(scene, si, &si, medium, sampler.next_2d(), sampler);
            if (!es.weight.is_black()) result += T * bsdf.eval(ctx, si, si.to_local(es.ds.d)) * es.weight;
        }
        break;
    }
    return result;
}

// Per pixel, the mean of `count` camera samples of `radiance` (non-finite ones dropped), each on
// its own stream Sampler(seed, pixel, k, stream); the first floor(sqrt(count))^2 samples are
// stratified over the pixel. Parallel over rows, deterministic for any thread count.
// `radiance` may also return a second value per sample in its last argument (0 on entry), averaged
// over the same samples into `aux` when given.
using CameraSampleValue = std::function<Color3(Sampler&, const Ray&, Color3&)>;
// Which samples: `count` per pixel of `grid`, on random stream `stream`.
struct CameraSamples {
    EstimateGrid grid;
    int count = 1;
    uint64_t stream = 0;
};
Image average_camera_samples(const Scene& scene, const CameraSamples& samples, const PreprocessContext& context,
                             const CameraSampleValue& radiance, Image* aux = nullptr) {
    const EstimateGrid grid = samples.grid;
    const int count = samples.count;
    const uint64_t stream = samples.stream;
    const Sensor& sensor = scene.sensor();
    const int W = grid.width, H = grid.height;
    const int strata = std::max(1, int(std::sqrt(float(count))));
    Image image(W, H);
    if (aux) *aux = Image(W, H);
    parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            if (context.cancelled()) return;
            for (int x = 0; x < W; ++x) {
                Color3 sum(0.f), aux_sum(0.f);
                for (int k = 0; k < count; ++k) {
                    Sampler sampler(context.seed, uint64_t(y) * uint64_t(W) + uint64_t(x), uint64_t(k), stream);
                    Vec2f u = sampler.next_2d();
                    if (k < strata * strata)
                        u = Vec2f((float(k % strata) + u.x) / float(strata), (float(k / strata) + u.y) / float(strata));
                    const Point2f pos = film_position(x, y, u);
                    const Point2f film_uv(pos.x / float(W), pos.y / float(H));
                    Color3 second(0.f);
                    const Color3 L = camera_sample_value(
                        sensor, film_uv, [&](const CameraRay& camera) { return radiance(sampler, camera.ray, second); });
                    if (L.is_finite() && second.is_finite()) {
                        sum += L;
                        aux_sum += second;
                    }
                }
                image.at(x, y) = sum * (1.f / float(count));
                if (aux) aux->at(x, y) = aux_sum * (1.f / float(count));
            }
        }
    });
    return image;
}

}  // namespace

PixelEstimate PixelEstimate::from_image(Image image, float floor_fraction) {
    PixelEstimate e;
    e.image_ = std::move(image);
    e.value_.resize(e.image_.pixels.size());
    double sum = 0.0;
    for (size_t i = 0; i < e.value_.size(); ++i) {
        const float v = e.image_.pixels[i].average();
        e.value_[i] = std::isfinite(v) && v > 0.f ? v : 0.f;
        sum += e.value_[i];
    }
    const double mean = e.value_.empty() ? 0.0 : sum / double(e.value_.size());
    // A black image still needs a positive I (every decision then compares with the floor).
    e.floor_ = std::max(float(floor_fraction * mean), 1e-6f);
    for (float& v : e.value_) v = std::max(v, e.floor_);
    return e;
}

EstimateGrid estimate_grid(int W, int H, long max_pixels) {
    if (long(W) * long(H) <= std::max(1L, max_pixels)) return {W, H};
    const double s = std::sqrt(double(W) * double(H) / double(std::max(1L, max_pixels)));
    return {std::max(1, int(double(W) / s)), std::max(1, int(double(H) / s))};
}

PixelEstimate PixelEstimate::raymarch(const Scene& scene, const GuidingField& field, const CacheEstimator& estimator,
                                      const PixelEstimateSettings& settings, const PreprocessContext& context) {
    const int rays = std::max(1, settings.rays_per_pixel);
    const Film& film = scene.sensor().film();
    EstimateGrid grid = estimate_grid(film.width(), film.height(), settings.max_pixels);
    auto march = [&](EstimateGrid g) {
        Image camera_segments;
        Image image = average_camera_samples(
            scene, CameraSamples{g, rays, kPixelEstimateStream}, context,
            [&](Sampler& sampler, const Ray& ray, Color3& camera_segment) {
                return march_camera_ray(estimator, settings, ray, sampler, camera_segment);
            },
            &camera_segments);
        PixelEstimate e = from_image(image, settings.floor_fraction);
        e.set_camera_scatter_probability(image, camera_segments);
        e.rays_ = uint64_t(g.width) * uint64_t(g.height) * uint64_t(rays);
        return e;
    };
    const long pixels = long(grid.width) * long(grid.height);
    if (!(settings.seconds > 0.0) || pixels <= kProbePixels) return march(grid);
    // Time limit: a coarse probe measures the time per ray; the final grid fits the rest of the time.
    const auto start = std::chrono::steady_clock::now();
    PixelEstimate probe = march(estimate_grid(grid.width, grid.height, kProbePixels));
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double per_pixel = spent / double(std::max<uint64_t>(1, probe.rays_ / uint64_t(rays)));
    const long affordable = per_pixel > 0.0 ? long(std::min(1e12, (settings.seconds - spent) / per_pixel)) : pixels;
    if (affordable <= kProbePixels) return probe;
    const uint64_t probe_rays = probe.rays_;
    PixelEstimate e = march(estimate_grid(grid.width, grid.height, std::min(pixels, affordable)));
    e.rays_ += probe_rays;
    return e;
}

void PixelEstimate::set_camera_scatter_probability(const Image& radiance, const Image& camera_segments) {
    // P_G = (what the camera segment scatters) / (all that arrives through it), per pixel over its
    // rays (docs/theory.md §7.10.2); NaN where no ray had a camera segment or nothing arrives.
    camera_vsp_.assign(radiance.pixels.size(), std::numeric_limits<float>::quiet_NaN());
    for (size_t i = 0; i < camera_vsp_.size(); ++i) {
        const float scattered = camera_segments.pixels[i].r, total = radiance.pixels[i].average();
        if (camera_segments.pixels[i].g > 0.f && total > 0.f && std::isfinite(total) && scattered >= 0.f)
            camera_vsp_[i] = std::min(scattered / total, 1.f);
    }
}

}  // namespace volguide
