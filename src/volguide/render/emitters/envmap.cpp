// `envmap`: latitude-longitude environment map, with Mitsuba 3's conventions:
//  - uv -> direction (emitter frame): theta = v pi, phi = u 2 pi,
//    d = (sin phi sin theta, cos theta, -cos phi sin theta): +y is up (v = 0), u = 0 looks down -z.
//  - The map is bilinearly interpolated; pixel x is centred on u = (x + 1/2) / width and row y sits at
//    v = y / (height - 1) (the first and last rows are the poles). A copy of the first column is
//    appended so the interpolation wraps around in u.
//  - Importance sampling follows the bilinear interpolant of luminance x sin(theta) on the same grid
//    (sampled in a frame shifted by half a texel in u), converted to solid angle by 1 / (2 pi^2 sin theta).
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>

#include "volguide/core/transform.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/bilinear_warp.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/render/image_io.h"

namespace volguide {
namespace {

constexpr float FloatEpsilon = 0x1p-24f;  // Mitsuba's dr::Epsilon<float>
constexpr float InvTwoPiSquared = float(1.0 / (2.0 * 3.14159265358979323846 * 3.14159265358979323846));

// Relative paths are tried as given (the loader may have resolved them), then next to the XML file.
std::string resolve_filename(const Properties& props, const std::string& name) {
    namespace fs = std::filesystem;
    const std::string file = props.get_string(name);
    if (fs::path(file).is_absolute() || fs::exists(file)) return file;
    const fs::path near_xml = fs::path(props.location_of(name).file).parent_path() / file;
    return fs::exists(near_xml) ? near_xml.string() : file;
}

class EnvironmentMapEmitter final : public Emitter {
  public:
    explicit EnvironmentMapEmitter(const Properties& props) {
        const std::string path = resolve_filename(props, "filename");
        Image image;
        try {
            image = read_image(path);
        } catch (const InputError& e) {
            props.fail_at("filename", "emitter 'envmap': {}", e.what());
        }
        if (image.width < 2 || image.height < 3)
            props.fail_at("filename", "emitter 'envmap': '{}': the resolution must be at least 2x3 pixels",
                          path);
        for (const Color3& c : image.pixels)
            if (!c.is_finite() || c.has_negative())
                props.fail_at("filename", "emitter 'envmap': '{}' has negative or non-finite pixels", path);
        scale_ = nonnegative_float(props, "scale", 1.f);
        const Transform to_world = props.get_transform("to_world");
        to_world_ = to_world;
        to_local_ = to_world.inverse();
        rotated_ = !to_world.is_identity();
        const bool mis_compensation = props.get_bool("mis_compensation", false);

        // Grid with the first column repeated at the end (periodic in u).
        width_ = image.width + 1;
        height_ = image.height;
        data_.resize(size_t(width_) * height_);
        for (int y = 0; y < height_; ++y) {
            for (int x = 0; x < image.width; ++x) data_[size_t(y) * width_ + x] = image.at(x, y);
            data_[size_t(y) * width_ + image.width] = image.at(0, y);
        }
        half_texel_ = 0.5f / float(width_ - 1);
        build_distribution(mis_compensation);
        flags_ = emitter_flags::Infinite;
        medium_ = emitter_medium(props);
    }

    void set_scene_bounds(const BBox3f& bounds) override { sphere_.set(bounds); }

    Color3 eval(const SurfaceInteraction& si) const override {
        return lookup(direction_to_uv(to_local(-si.wi)));
    }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f u) const override {
        return sample_with(warp_, ref, u);
    }

    // Direction by the map's own importance sampling (without MIS compensation, which would leave
    // dim regions unsampled and bias the photons), origin on the bounding sphere's disk.
    RaySample sample_ray(Point2f u_pos, Point2f u_dir) const override {
        Interaction ref;
        ref.p = sphere_.center;
        auto [ds, weight] = sample_with(emission_warp(), ref, u_dir);
        if (!(ds.pdf > 0.f)) return RaySample{};
        return infinite_emitter_ray(sphere_, ds.d, weight, u_pos);
    }

    // E[weight] = disk area x integral of the radiance over the sphere of directions.
    Color3 power() const override { return radiance_integral_ * sphere_.disk_area(); }

    float pdf_direction(const Interaction&, const DirectionSample& ds) const override {
        if (!warp_.valid()) return 0.f;
        const Vec3f d = to_local(ds.d);
        Point2f uv = direction_to_uv(d);
        uv.x -= half_texel_;
        uv.x -= std::floor(uv.x);
        uv.y -= std::floor(uv.y);
        const float inv_sin_theta =
            1.f / std::sqrt(std::max(d.x * d.x + d.z * d.z, FloatEpsilon * FloatEpsilon));
        return warp_.pdf(uv) * inv_sin_theta * InvTwoPiSquared;
    }

    std::string to_string() const override {
        return fmt::format("EnvironmentMapEmitter[{}x{}]", width_ - 1, height_);
    }

  private:
    const BilinearWarp2D& emission_warp() const { return emission_warp_.valid() ? emission_warp_ : warp_; }

    // Mitsuba's envmap sample_direction with the given warp of the (shifted) uv square.
    std::pair<DirectionSample, Color3> sample_with(const BilinearWarp2D& warp, const Interaction& ref,
                                                   Point2f u) const {
        DirectionSample ds;
        ds.emitter = this;
        ds.delta = false;
        ds.dist = Infinity;
        auto [grid_uv, grid_pdf] = warp.sample(u);
        if (!(grid_pdf > 0.f)) return {ds, Color3(0.f)};

        const Point2f uv{grid_uv.x + half_texel_, grid_uv.y};
        const float theta = uv.y * Pi, phi = uv.x * (2.f * Pi);
        const float sin_theta = std::sin(theta), cos_theta = std::cos(theta);
        const Vec3f local{std::sin(phi) * sin_theta, cos_theta, -std::cos(phi) * sin_theta};
        const float inv_sin_theta = 1.f / std::max(sin_theta, FloatEpsilon);

        ds.d = rotated_ ? normalize(to_world_.apply_vector(local)) : local;
        ds.p = ref.p + ds.d * sphere_.sample_distance(ref.p);
        ds.n = -ds.d;
        ds.uv = uv;
        ds.pdf = grid_pdf * inv_sin_theta * InvTwoPiSquared;
        return {ds, lookup(uv) / ds.pdf};
    }

    Vec3f to_local(const Vec3f& world) const {
        return rotated_ ? normalize(to_local_.apply_vector(world)) : normalize(world);
    }

    static Point2f direction_to_uv(const Vec3f& d) {
        return {std::atan2(d.x, -d.z) * InvTwoPi, safe_acos(d.y) * InvPi};
    }

    // Bilinear lookup of the (padded) map at uv, times `scale`.
    Color3 lookup(Point2f uv) const {
        uv.x -= half_texel_;
        uv.x -= std::floor(uv.x);
        uv.y -= std::floor(uv.y);
        const float x = uv.x * float(width_ - 1), y = uv.y * float(height_ - 1);
        const int ix = std::min(int(x), width_ - 2), iy = std::min(int(y), height_ - 2);
        const float fx = x - ix, fy = y - iy;
        const Color3* row0 = &data_[size_t(iy) * width_ + ix];
        const Color3* row1 = row0 + width_;
        const Color3 v0 = (1.f - fx) * row0[0] + fx * row0[1];
        const Color3 v1 = (1.f - fx) * row1[0] + fx * row1[1];
        return ((1.f - fy) * v0 + fy * v1) * scale_;
    }

    void build_distribution(bool mis_compensation) {
        radiance_integral_ = integrate_radiance();
        if (mis_compensation) emission_warp_ = make_warp(false);
        warp_ = make_warp(mis_compensation);
    }

    // Integral of the bilinear map over solid angle, d omega = 2 pi^2 sin(pi v) du dv. Over a full
    // period in u each row's interpolant averages to the mean of its pixels m_y; between rows y and
    // y+1 (v = (y + t) h, h = 1 / (height - 1)) the interpolant is linear in t, and
    // int_0^1 (m_y (1 - t) + m_{y+1} t) sin(a + b t) dt is closed-form (a = pi y h, b = pi h).
    Color3 integrate_radiance() const {
        const int w = width_ - 1;  // the original columns
        std::vector<std::array<double, 3>> row_mean(height_);
        for (int y = 0; y < height_; ++y) {
            std::array<double, 3> m{0.0, 0.0, 0.0};
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) m[c] += data_[size_t(y) * width_ + x][c];
            for (int c = 0; c < 3; ++c) row_mean[y][c] = m[c] / w;
        }
        const double pi = 3.14159265358979323846, h = 1.0 / double(height_ - 1), b = pi * h;
        std::array<double, 3> sum{0.0, 0.0, 0.0};
        for (int y = 0; y + 1 < height_; ++y) {
            const double a = pi * y * h;
            const double s0 = (std::cos(a) - std::cos(a + b)) / b;  // int sin(a + b t)
            const double s1 = -std::cos(a + b) / b + (std::sin(a + b) - std::sin(a)) / (b * b);  // int t sin
            for (int c = 0; c < 3; ++c) sum[c] += row_mean[y][c] * (s0 - s1) + row_mean[y + 1][c] * s1;
        }
        const double k = 2.0 * pi * pi * h * scale_;
        return Color3(float(sum[0] * k), float(sum[1] * k), float(sum[2] * k));
    }

    BilinearWarp2D make_warp(bool mis_compensation) const {
        std::vector<float> lum(data_.size());
        for (size_t i = 0; i < data_.size(); ++i) lum[i] = data_[i].luminance();

        // MIS compensation (Karlik et al. 2019): subtract the average luminance, unless the map is
        // nearly constant.
        float offset = 0.f;
        if (mis_compensation) {
            double sum = 0.0;
            float min_lum = Infinity;
            for (int y = 0; y < height_; ++y)
                for (int x = 0; x < width_ - 1; ++x) {
                    const float l = lum[size_t(y) * width_ + x];
                    min_lum = std::min(min_lum, l);
                    sum += l;
                }
            offset = float(sum / (double(width_ - 1) * height_));
            if (offset - min_lum <= 0.01f * offset) offset = 0.f;
        }
        for (int y = 0; y < height_; ++y) {
            // sin(pi) is slightly negative in float: clamp so the last row stays a zero weight.
            const float sin_theta = std::max(0.f, float(std::sin(y * Pi / float(height_ - 1))));
            for (int x = 0; x < width_; ++x) {
                float& l = lum[size_t(y) * width_ + x];
                l = std::max(l - offset, 0.f) * sin_theta;
            }
        }
        return BilinearWarp2D(std::move(lum), width_, height_);
    }

    int width_ = 0, height_ = 0;  // of the padded grid
    std::vector<Color3> data_;
    float scale_ = 1.f;
    float half_texel_ = 0.f;
    Transform to_world_, to_local_;
    bool rotated_ = false;
    BilinearWarp2D warp_;
    BilinearWarp2D emission_warp_;  // without MIS compensation; only built when warp_ has it
    Color3 radiance_integral_{0.f};  // integral of the radiance over solid angle (W / m^2)
    InfiniteEmitterSphere sphere_;
};

}  // namespace

ObjectPtr make_envmap_emitter(const Properties& props) {
    return std::make_shared<EnvironmentMapEmitter>(props);
}

}  // namespace volguide
