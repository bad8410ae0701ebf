#pragma once
// The measured per-tile method choice (issue 55): per 16 x 16 film tile, either the guided
// configuration or volpath with rr_rule=bounded renders the tile's pixels for the whole render. Both are
// unbiased estimators of the pixel, so a map fixed before the first image pass keeps the image unbiased.
// The map is decided in the pre-pass from probes: one pixel in four of every tile (a checkerboard of
// 2 x 2 blocks) renders a few camera samples with each method on the probes' own random streams (not in
// the image). Per tile and method: the per-sample relative variance (the pixel's unbiased variance over
// (m^2 + 0.01), m the pixel's mean over both methods, averaged over the tile's probe pixels, as
// PassReport's) and the counted cost per sample (WorkCounter: no wall clock, so the same seed and sample
// count give the same map for any thread count and in every distributed chunk).
// A tile goes to volpath only when the evidence says so with confidence (decide_tile): the log of the
// efficiency ratio (V_g C_g) / (V_v C_v) must exceed z standard errors, the error from the spread of
// the per-pixel variance estimates over the tile (so their own variance, the fourth moment, is in it)
// and of the costs; the tile alone and pooled with its 3 x 3 neighbourhood must both say so. A volpath
// tile whose probes saw no variance while guided's did stays guided, and so does a tile whose volpath probes
// have fewer than 4 samples per probe pixel (volpath's rare bright paths the probes may not have seen must
// not decide a tile).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/image.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class Scene;

enum class TileMethod : uint8_t { Guided = 0, Volpath = 1 };

// The counted work of one camera sample (all its branches), in cost units: fixed weights calibrated once
// against measured ns (bench/RESULTS.md, "issue 55 — per-tile choice"). Deterministic by construction.
class WorkCounter final : public PathRecorder {
public:
    // The weights, in ns of one core's CPU time on the calibration machine (a least-squares fit to the probes'
    // CPU time on the nine benchmark scenes; bench/RESULTS.md, "issue 55 — per-tile choice"). Heterogeneous
    // media's tracking steps and the guided distance decision's leaves are not counted (RESULTS.md has how
    // far the model's guided/volpath cost ratio is from the measured one).
    static constexpr double kSegment = 380;             // a ray segment (each surface hit, escape or medium scattering)
    static constexpr double kMediumVertex = 720;        // a medium scattering: NEE through media + phase sampling
    static constexpr double kSurfaceVertex = 150;       // a surface scattering: NEE + BSDF sampling
    static constexpr double kGuidedMediumVertex = 400;  // a guided medium vertex's decisions, on top
    static constexpr double kGuidedSurfaceVertex = 1160;  // a guided surface vertex's decision, on top
    static constexpr double kContinuation = 100;        // a continuation decision (guided RR/splitting)
    static constexpr double kBranch = 5200;             // a split copy (its set-up and the vertex it resumes)
    static constexpr int kCounts = 5;  // segments, medium vertices, surface vertices, continuations, branches
    explicit WorkCounter(bool guided) : guided_(guided) {}
    void reset() { segments_ = medium_ = surface_ = continuations_ = branches_ = 0; }
    double cost() const;
    // The counts (kCounts, in the order above), for the cost model's calibration (--stats).
    void counts(double* out) const;
    void record_medium_hit(const MediumInteraction&) override { ++medium_; }
    void record_surface_hit(const SurfaceInteraction&) override { ++segments_; }
    void record_surface_vertex(const SurfaceInteraction&, const BSDFSample&, const Vec3f&, const Color3&) override {
        ++surface_;
    }
    void record_continuation(ContinuationStage, int, const Vec3f&, float, const Color3&) override {
        ++continuations_;
    }
    void end_camera_sample(int branches) override { branches_ += branches > 1 ? branches - 1 : 0; }

private:
    bool guided_;
    int64_t segments_ = 0, medium_ = 0, surface_ = 0, continuations_ = 0, branches_ = 0;
};

// What one method's probes say of one tile (or of a pooled neighbourhood: the sums add).
struct TileEvidence {
    double pixels = 0, var_sum = 0, var_sq = 0;   // probe pixels with >= 2 samples; sums of their relative variance
    double samples = 0, cost_sum = 0, cost_sq = 0;  // probe samples; sums of their cost
    void add(const TileEvidence& o);
    // One probe pixel's samples of this method: count n, sums of the luminance x and x^2 and of the cost c
    // and c^2; `pooled_mean` the pixel's mean over both methods (the relative variance's normaliser).
    void add_pixel(double n, double x, double x2, double c, double c2, double pooled_mean);
    double variance() const { return pixels > 0 ? var_sum / pixels : 0.0; }
    double cost() const { return samples > 0 ? cost_sum / samples : 0.0; }
    // Squared standard errors of variance() and cost() (sample variance over the count).
    double variance_error2() const;
    double cost_error2() const;
};

struct TileDecision {
    TileMethod method = TileMethod::Guided;
    double log_ratio = 0;  // log((V_g C_g) / (V_v C_v)): > 0 volpath is more efficient
    double error = 0;      // its standard error
};

// The decision rule for one tile (see the file comment); z: the standard errors the evidence needs.
inline constexpr double kChoiceConfidence = 3.0;
TileDecision decide_tile(const TileEvidence& guided, const TileEvidence& volpath, double z = kChoiceConfidence);

// The map over the film: tile (tx, ty) covers pixels [16 tx, 16 tx + 16) x [16 ty, 16 ty + 16).
struct ChoiceMap {
    static constexpr int kTile = 16;
    int width = 0, height = 0;  // the film's
    std::vector<TileMethod> tiles;  // row-major, tiles_x() x tiles_y(); empty: no choice (every tile guided)
    int tiles_x() const { return (width + kTile - 1) / kTile; }
    int tiles_y() const { return (height + kTile - 1) / kTile; }
    bool empty() const { return tiles.empty(); }
    // The method of the tile under film_uv (a filter's border clamps to the nearest tile).
    TileMethod at(Point2f film_uv) const;
    double volpath_share() const;
    // One pixel per film pixel: white where volpath renders, dark blue where guided does.
    Image image() const;
    std::string serialize() const;
    static ChoiceMap deserialize(const std::string& bytes);  // throws std::runtime_error
};

// The probes' sums per probe pixel and method, filled round by round (one sample per probe pixel and
// method per round); each probe pixel is written by one task in round order: exact for any thread count.
class ChoiceProbes {
public:
    ChoiceProbes(int width, int height);
    // Whether film pixel (x, y) is a probe pixel.
    static bool is_probe(int x, int y) { return y % 2 == 0 && x % 2 == (y / 2) % 2; }
    // `walk(sampler, camera, counter)`: the method's radiance along the camera ray, its work counted.
    using Walk = std::function<Color3(Sampler&, const CameraRay&, WorkCounter&)>;
    // Sample `round` of every probe pixel with `method` (stream `stream`, seed `seed`).
    void run_round(const Scene& scene, TileMethod method, uint64_t seed, uint64_t stream, int round, const Walk& walk);
    // Forget one method's samples (the guided probes again with the full field).
    void clear(TileMethod method);
    // Per tile (row-major) one method's evidence; the pixels' means pool both methods' samples.
    std::vector<TileEvidence> evidence(TileMethod method) const;
    int probe_pixels() const { return int(pixels_.size()); }
    // One method's counted cost and samples over every probe pixel (statistics: the cost model's check).
    double total_cost(TileMethod method) const;
    double total_samples(TileMethod method) const;
    double total_count(TileMethod method, int count) const;

private:
    struct Sums {
        double n = 0, x = 0, x2 = 0, c = 0, c2 = 0;
        double counts[WorkCounter::kCounts] = {};
    };
    struct Pixel {
        int x = 0, y = 0;
        Sums m[2];
    };
    int width_, height_;
    std::vector<Pixel> pixels_;
};

// The map from both methods' evidence: a tile is volpath's when it and its 3 x 3 neighbourhood pooled
// both decide so (decide_tile), and, in tile order, switching it lowers the whole image's variance x time
// (every pixel gets the same spp: a tile's saved time buys samples for all tiles, not for itself).
ChoiceMap decide_map(int width, int height, const std::vector<TileEvidence>& guided,
                     const std::vector<TileEvidence>& volpath, double z = kChoiceConfidence);

}  // namespace volguide
