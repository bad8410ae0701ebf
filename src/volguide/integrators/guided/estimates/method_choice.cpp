#include "volguide/integrators/guided/estimates/method_choice.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

constexpr uint32_t kChoiceFormatVersion = 1;
// The pixel normaliser's epsilon: the benchmark's relMSE epsilon, as PassReport's.
constexpr double kRelativeEpsilon = 0.01;
// Fewer probe pixels than this in a tile (or its neighbourhood): no evidence, the tile stays guided.
constexpr double kMinPixels = 4;
// Volpath's probes need this many samples per probe pixel before a tile may go to volpath: with fewer, its
// rare bright paths are too likely to be unseen (at 2 samples a pixel, backlit's 1-spp volpath tiles are
// fireflies the probes never showed; tests/scripts/test_bench_harness.sh's cross-check).
constexpr double kMinSamplesPerPixel = 4;

void put_u32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(char(uint8_t(v >> (8 * i))));
}
uint32_t get_u32(const std::string& s, size_t pos) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(s[pos + size_t(i)])) << (8 * i);
    return v;
}

// Sample variance over the count of `n` values with sum `s` and sum of squares `s2`.
double mean_error2(double n, double s, double s2) {
    if (n < 2) return 0.0;
    const double mean = s / n;
    return std::max(0.0, (s2 - n * mean * mean) / (n - 1)) / n;
}

}  // namespace

double WorkCounter::cost() const {
    double c = kSegment * double(segments_ + medium_) + kMediumVertex * double(medium_) +
               kSurfaceVertex * double(surface_);
    if (guided_)
        c += kGuidedMediumVertex * double(medium_) + kGuidedSurfaceVertex * double(surface_) +
             kContinuation * double(continuations_) + kBranch * double(branches_);
    return c;
}

void WorkCounter::counts(double* out) const {
    out[0] = double(segments_ + medium_);
    out[1] = double(medium_);
    out[2] = double(surface_);
    out[3] = double(continuations_);
    out[4] = double(branches_);
}

void TileEvidence::add(const TileEvidence& o) {
    pixels += o.pixels;
    var_sum += o.var_sum;
    var_sq += o.var_sq;
    samples += o.samples;
    cost_sum += o.cost_sum;
    cost_sq += o.cost_sq;
}

void TileEvidence::add_pixel(double n, double x, double x2, double c, double c2, double pooled_mean) {
    samples += n;
    cost_sum += c;
    cost_sq += c2;
    if (n < 2) return;
    const double mean = x / n;
    const double rel = std::max(0.0, (x2 - n * mean * mean) / (n - 1)) / (pooled_mean * pooled_mean + kRelativeEpsilon);
    pixels += 1;
    var_sum += rel;
    var_sq += rel * rel;
}

double TileEvidence::variance_error2() const { return mean_error2(pixels, var_sum, var_sq); }
double TileEvidence::cost_error2() const { return mean_error2(samples, cost_sum, cost_sq); }

TileDecision decide_tile(const TileEvidence& guided, const TileEvidence& volpath, double z) {
    TileDecision d;
    if (guided.pixels < kMinPixels || volpath.pixels < kMinPixels) return d;
    if (volpath.samples < kMinSamplesPerPixel * volpath.pixels) return d;
    const double Vg = guided.variance(), Vv = volpath.variance();
    const double Cg = std::max(guided.cost(), 1e-9), Cv = std::max(volpath.cost(), 1e-9);
    double e2 = guided.cost_error2() / (Cg * Cg) + volpath.cost_error2() / (Cv * Cv);
    if (Vv <= 0 && Vg > 0) return d;  // volpath saw no variance where guided did: unseen tails, stay guided
    if (Vg > 0) {
        // Both saw variance: the efficiency ratio with both estimates' errors (delta method on the log).
        d.log_ratio = std::log(Vg * Cg) - std::log(Vv * Cv);
        e2 += guided.variance_error2() / (Vg * Vg) + volpath.variance_error2() / (Vv * Vv);
    } else if (Vv > 0) {
        return d;  // guided saw none, volpath some: guided
    } else {
        d.log_ratio = std::log(Cg) - std::log(Cv);  // neither saw variance: the cost decides
    }
    d.error = std::sqrt(e2);
    if (d.log_ratio > z * d.error) d.method = TileMethod::Volpath;
    return d;
}

TileMethod ChoiceMap::at(Point2f film_uv) const {
    if (tiles.empty()) return TileMethod::Guided;
    const int tx = std::clamp(int(std::floor(film_uv.x * float(width))) / kTile, 0, tiles_x() - 1);
    const int ty = std::clamp(int(std::floor(film_uv.y * float(height))) / kTile, 0, tiles_y() - 1);
    return tiles[size_t(ty) * size_t(tiles_x()) + size_t(tx)];
}

double ChoiceMap::volpath_share() const {
    if (tiles.empty()) return 0.0;
    return double(std::count(tiles.begin(), tiles.end(), TileMethod::Volpath)) / double(tiles.size());
}

Image ChoiceMap::image() const {
    Image img(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Point2f uv((float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height));
            img.at(x, y) = at(uv) == TileMethod::Volpath ? Color3(1.f) : Color3(0.05f, 0.1f, 0.4f);
        }
    return img;
}

std::string ChoiceMap::serialize() const {
    std::string s;
    put_u32(s, kChoiceFormatVersion);
    put_u32(s, uint32_t(width));
    put_u32(s, uint32_t(height));
    put_u32(s, uint32_t(kTile));
    for (TileMethod m : tiles) s.push_back(char(m));
    return s;
}

ChoiceMap ChoiceMap::deserialize(const std::string& bytes) {
    if (bytes.size() < 16) throw std::runtime_error("truncated method choice map");
    if (get_u32(bytes, 0) != kChoiceFormatVersion)
        throw std::runtime_error("unsupported method choice map version " + std::to_string(get_u32(bytes, 0)));
    ChoiceMap map;
    map.width = int(get_u32(bytes, 4));
    map.height = int(get_u32(bytes, 8));
    if (get_u32(bytes, 12) != uint32_t(kTile) || map.width <= 0 || map.height <= 0 || map.width > 65536 ||
        map.height > 65536 || bytes.size() - 16 != size_t(map.tiles_x()) * size_t(map.tiles_y()))
        throw std::runtime_error("method choice map: its size does not match its data");
    for (size_t i = 16; i < bytes.size(); ++i) {
        const uint8_t m = uint8_t(bytes[i]);
        if (m > 1) throw std::runtime_error("method choice map: unknown method");
        map.tiles.push_back(TileMethod(m));
    }
    return map;
}

ChoiceProbes::ChoiceProbes(int width, int height) : width_(width), height_(height) {
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (is_probe(x, y)) pixels_.push_back(Pixel{x, y, {}});
}

void ChoiceProbes::run_round(const Scene& scene, TileMethod method, uint64_t seed, uint64_t stream, int round,
                             const Walk& walk) {
    const Sensor& sensor = scene.sensor();
    const int m = int(method);
    parallel_for(tbb::blocked_range<size_t>(0, pixels_.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
        WorkCounter counter(method == TileMethod::Guided);
        for (size_t i = r.begin(); i != r.end(); ++i) {
            Pixel& p = pixels_[i];
            Sampler sampler(seed, uint64_t(p.y) * uint64_t(width_) + uint64_t(p.x), uint64_t(round), stream);
            const Point2f pos = film_position(p.x, p.y, sampler.next_2d());
            const Point2f film_uv(pos.x / float(width_), pos.y / float(height_));
            const Point2f aperture = sensor.needs_aperture_sample() ? sampler.next_2d() : Point2f(0.5f, 0.5f);
            counter.reset();
            const Color3 L = camera_sample_value(
                sensor, film_uv, [&](const CameraRay& camera) { return walk(sampler, camera, counter); }, aperture);
            const double x = std::isfinite(L.luminance()) ? double(L.luminance()) : 0.0;
            const double c = counter.cost();
            Sums& s = p.m[m];
            s.n += 1;
            s.x += x;
            s.x2 += x * x;
            s.c += c;
            s.c2 += c * c;
            double counts[WorkCounter::kCounts];
            counter.counts(counts);
            for (int k = 0; k < WorkCounter::kCounts; ++k) s.counts[k] += counts[k];
        }
    });
}

void ChoiceProbes::clear(TileMethod method) {
    for (Pixel& p : pixels_) p.m[int(method)] = Sums{};
}

double ChoiceProbes::total_cost(TileMethod method) const {
    double c = 0;
    for (const Pixel& p : pixels_) c += p.m[int(method)].c;
    return c;
}

double ChoiceProbes::total_samples(TileMethod method) const {
    double n = 0;
    for (const Pixel& p : pixels_) n += p.m[int(method)].n;
    return n;
}

double ChoiceProbes::total_count(TileMethod method, int count) const {
    double n = 0;
    for (const Pixel& p : pixels_) n += p.m[int(method)].counts[count];
    return n;
}

std::vector<TileEvidence> ChoiceProbes::evidence(TileMethod method) const {
    ChoiceMap shape{width_, height_, {}};
    std::vector<TileEvidence> tiles(size_t(shape.tiles_x()) * size_t(shape.tiles_y()));
    const int m = int(method);
    for (const Pixel& p : pixels_) {
        TileEvidence& t = tiles[size_t(p.y / ChoiceMap::kTile) * size_t(shape.tiles_x()) + size_t(p.x / ChoiceMap::kTile)];
        const Sums& s = p.m[m];
        const double n_all = p.m[0].n + p.m[1].n;
        t.add_pixel(s.n, s.x, s.x2, s.c, s.c2, n_all > 0 ? (p.m[0].x + p.m[1].x) / n_all : 0.0);
    }
    return tiles;
}

namespace {

// The render loop gives every pixel the same spp: the image's relative variance per sample is the sum over
// tiles of their variance sums, its time the sum of their costs, and a render of fixed time has an error
// proportional to their product. A tile the per-tile rule sends to volpath goes there only while that lowers
// the product (its saved time buys samples for every tile; its own variance stays at the common spp).
void keep_what_lowers_the_product(ChoiceMap& map, const std::vector<TileEvidence>& guided,
                                  const std::vector<TileEvidence>& volpath) {
    auto var = [](const TileEvidence& e) { return e.var_sum; };
    auto cost = [](const TileEvidence& e) { return e.cost() * e.pixels; };
    double V = 0, C = 0;
    for (size_t i = 0; i < guided.size(); ++i) {
        V += var(guided[i]);
        C += cost(guided[i]);
    }
    for (size_t i = 0; i < map.tiles.size(); ++i) {
        if (map.tiles[i] != TileMethod::Volpath) continue;
        const double v = V - var(guided[i]) + var(volpath[i]), c = C - cost(guided[i]) + cost(volpath[i]);
        if (v * c < V * C) {
            V = v;
            C = c;
        } else {
            map.tiles[i] = TileMethod::Guided;
        }
    }
}

}  // namespace

ChoiceMap decide_map(int width, int height, const std::vector<TileEvidence>& guided,
                     const std::vector<TileEvidence>& volpath, double z) {
    ChoiceMap map{width, height, {}};
    const int tx = map.tiles_x(), ty = map.tiles_y();
    map.tiles.assign(size_t(tx) * size_t(ty), TileMethod::Guided);
    for (int y = 0; y < ty; ++y)
        for (int x = 0; x < tx; ++x) {
            const size_t i = size_t(y) * size_t(tx) + size_t(x);
            if (decide_tile(guided[i], volpath[i], z).method != TileMethod::Volpath) continue;
            TileEvidence g, v;
            for (int ny = std::max(0, y - 1); ny <= std::min(ty - 1, y + 1); ++ny)
                for (int nx = std::max(0, x - 1); nx <= std::min(tx - 1, x + 1); ++nx) {
                    g.add(guided[size_t(ny) * size_t(tx) + size_t(nx)]);
                    v.add(volpath[size_t(ny) * size_t(tx) + size_t(nx)]);
                }
            map.tiles[i] = decide_tile(g, v, z).method;
        }
    keep_what_lowers_the_product(map, guided, volpath);
    return map;
}

}  // namespace volguide
