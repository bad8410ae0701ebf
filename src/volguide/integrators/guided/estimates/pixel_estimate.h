#pragma once
// The pixel estimate I of guided Russian roulette and splitting (docs/theory.md §9.5, eq. 9.2): the
// value each pixel is expected to converge to, against which a partial path's expected
// contribution is compared (roulette_splitting.h).
//
// raymarch: after training, M jittered camera rays per pixel (stratified in the pixel, M =
// `rays_per_pixel`) are marched through the guiding field: the in-scattered radiance
// T sigma_s L~_i along every medium segment (CacheEstimator's march, the field's own prediction),
// across null surfaces, following one sampled lobe of purely specular surfaces (a dielectric
// sphere's refraction into its medium), plus the attenuated emission of a visible emitter or the
// environment. At the first rough surface its outgoing radiance is estimated as diffuse: the albedo
// (one BSDF sample's weight) times the irradiance over pi, the irradiance in closed form from the
// field's leaf on the side the ray arrives from (direct and indirect light) or, where there is no
// valid leaf at least half filled by a medium (a surface in vacuum), from one NEE sample through
// the media. volume_only: the V
// image's estimate, the media in front of the first real surface.
//
// raymarch also fills distance="vsp"'s camera-ray buffer (camera_scatter_probability).
//
// Its cost is bounded (issue 55): at most max_pixels estimate pixels, a regular grid over the film coarser
// than the film's pixels where the film has more (at() reads it by film position), and within `seconds`
// when given: a first grid of at most kProbePixels measures the time per ray, and the final grid is
// the largest that fits the rest of the time (the probe's grid if none does). Without a time limit the
// grid depends only on the film's size: deterministic.
//
// The estimate is stored per pixel as the channel average and floored at `floor_fraction` of the
// image mean, so that a pixel the field thinks black cannot make every path through it split to
// the cap (docs/theory.md §13.13).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "volguide/core/image.h"
#include "volguide/core/progress.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/core/vec.h"

namespace volguide {

class Scene;
class GuidingField;
class CacheEstimator;
struct PreprocessContext;

struct PixelEstimateSettings {
    int rays_per_pixel = 4;
    float floor_fraction = 0.01f;
    bool volume_only = false;
    bool hide_emitters = false;
    int max_specular_events = 16;
    int max_pixels = 256 * 256;  // the estimate's resolution at most (a 1024 x 1024 film: a 4 x 4 block each)
    double seconds = 0.0;        // time limit (0: none)
};

// The estimate's grid for a film of W x H pixels: the film's own, or a coarser one of the same aspect
// with at most max_pixels pixels.
struct EstimateGrid {
    int width = 0, height = 0;
};
EstimateGrid estimate_grid(int W, int H, long max_pixels);

class PixelEstimate {
  public:
    PixelEstimate() = default;
    // Marches the scene's sensor: deterministic for a seed, any thread count.
    static PixelEstimate raymarch(const Scene& scene, const GuidingField& field, const CacheEstimator& estimator,
                                  const PixelEstimateSettings& settings, const PreprocessContext& context);
    // From a given RGB image (the film's resolution): channel averages, floored.
    static PixelEstimate from_image(Image image, float floor_fraction);

    bool empty() const { return image_.pixels.empty(); }
    // I at a film position (film uv in [0, 1]^2; positions outside, from a filter's border, clamp).
    float at(Point2f film_uv) const {
        const int x = std::clamp(int(film_uv.x * float(image_.width)), 0, image_.width - 1);
        const int y = std::clamp(int(film_uv.y * float(image_.height)), 0, image_.height - 1);
        return value_[size_t(y) * size_t(image_.width) + size_t(x)];
    }
    // What the learning divides a camera sample by (allocation.h): sqrt(I^2 + kMetricEpsilon), I the
    // estimate before its floor, so that (X / scale)^2 weighs pixels as the benchmark's relMSE weighs
    // them (error^2 / (reference^2 + 0.01), docs/theory.md §22.4): a pixel the field thinks black does
    // not count as if its every sample were an outlier.
    static constexpr float kMetricEpsilon = 0.01f;
    float metric_scale(Point2f film_uv) const {
        const int x = std::clamp(int(film_uv.x * float(image_.width)), 0, image_.width - 1);
        const int y = std::clamp(int(film_uv.y * float(image_.height)), 0, image_.height - 1);
        const float v = image_.pixels[size_t(y) * size_t(image_.width) + size_t(x)].average();
        return std::sqrt(v * v + kMetricEpsilon);
    }
    // distance="vsp"'s camera-ray buffer (docs/theory.md §7.10.2; raymarch only): per pixel, the share
    // of what its camera rays' first medium segment (before any real surface) scatters toward the
    // camera in all the ray brings, the zero-variance scatter probability of that segment estimated
    // once per pixel for all its samples; NaN where there is none (no buffer, no such segment).
    float camera_scatter_probability(Point2f film_uv) const {
        if (camera_vsp_.empty()) return std::numeric_limits<float>::quiet_NaN();
        const int x = std::clamp(int(film_uv.x * float(image_.width)), 0, image_.width - 1);
        const int y = std::clamp(int(film_uv.y * float(image_.height)), 0, image_.height - 1);
        return camera_vsp_[size_t(y) * size_t(image_.width) + size_t(x)];
    }
    // The rays the raymarch traced (its cost; 0 for from_image).
    uint64_t rays() const { return rays_; }
    static constexpr long kProbePixels = 64 * 64;
    // The RGB estimate before flooring (for inspection and the comparison with references).
    const Image& image() const { return image_; }
    float floor() const { return floor_; }

  private:
    // camera_vsp_ from the raymarch's radiance and camera-segment images.
    void set_camera_scatter_probability(const Image& radiance, const Image& camera_segments);

    Image image_;
    std::vector<float> value_;  // floored channel averages, row-major
    std::vector<float> camera_vsp_;  // camera_scatter_probability per pixel, row-major (empty: none)
    float floor_ = 0.f;
    uint64_t rays_ = 0;
};

}  // namespace volguide
