// Embedding volguide's guiding core in a renderer of one's own (docs/guiding-api.md).
//
// The "renderer" here is a 1-D world: a homogeneous slab 0 <= z <= D, infinite in x and y, lit from
// below by a collimated beam travelling along +z (irradiance E0 on the plane z = 0), isotropic
// phase function. It has no scene and no walk of volguide's; it uses
//   - GuidingField::build on photon collisions it traces itself, save_field / load_field;
//   - the guided distance sampler over bins it makes itself (its own sigma_t, albedo and the
//     field's L~_i, L~ at each bin);
//   - the continuation decision (RouletteSplitting::factor, stochastic_round);
//   - the guided direction sampler with its own PhaseFunction.
// and checks what the guarantees say: the sampled distance pdf integrates to one and is the density
// the sampler draws from; the guided estimate of the single-scattered radiance along a view ray is
// unbiased against its closed form although the field (trained on all orders of scattering) is
// only an approximation of that integrand; Russian roulette and splitting keep it unbiased; the
// direction sampler's weights f_p / p integrate the phase function to one. Exit status 1 on a
// failed check.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "volguide/guiding/field_io.h"
#include "volguide/guiding/guided_direction.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/media/phase.h"
#include "volguide/vmm/phase_vmm.h"

using namespace volguide;

namespace {

constexpr float kPi = 3.14159265358979f;

struct Slab {
    float sigma_t = 2.f;   // grey extinction [1/length]
    float albedo = 0.8f;
    float depth = 1.5f;    // D
    float E0 = 1.f;        // beam irradiance at z = 0
    float half_width = 0.05f;  // the field covers a column |x|, |y| <= half_width (the slab is 1-D)
    float sigma_s() const { return albedo * sigma_t; }
    BBox3f column() const { return {Point3f(-half_width, -half_width, 0.f), Point3f(half_width, half_width, depth)}; }
};

// Any type with next_1d() in [0, 1) drives the samplers; this one is splitmix64.
struct Rng {
    uint64_t state;
    float next_1d() {
        uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        return float(z >> 40) * 0x1p-24f;
    }
};

Vec3f uniform_sphere(float u1, float u2) {
    const float z = 1.f - 2.f * u1, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// The renderer's own phase function (volguide's interface, media/phase.h).
class IsotropicPhase : public PhaseFunction {
  public:
    PhaseSample sample(const Vec3f&, Point2f u) const override {
        return {uniform_sphere(u.x, u.y), 1.f / (4.f * kPi), 1.f};
    }
    float eval(const Vec3f&, const Vec3f&) const override { return 1.f / (4.f * kPi); }
    float mean_cosine() const override { return 0.f; }
};

// Training data: photon collisions in the slab, all orders of scattering (the absorbed share is
// taken from the photon's power). Each collision is a RadianceSample with the direction towards
// where the photon came from and the collision estimator's weight Phi_p / sigma_t (PerVolume).
// x and y wrap around the column: the slab is the same everywhere.
std::vector<RadianceSample> trace_photons(const Slab& slab, int photons, Rng& rng) {
    std::vector<RadianceSample> samples;
    const float w = slab.half_width;
    const float area = 4.f * w * w;
    auto wrap = [w](float v) { return v - 2.f * w * std::floor((v + w) / (2.f * w)); };
    for (int i = 0; i < photons; ++i) {
        Point3f p(w * (2.f * rng.next_1d() - 1.f), w * (2.f * rng.next_1d() - 1.f), 0.f);
        Vec3f d(0.f, 0.f, 1.f);
        float power = slab.E0 * area / float(photons);
        for (int bounce = 0; bounce < 64 && power > 0.f; ++bounce) {
            const float t = -std::log(1.f - rng.next_1d()) / slab.sigma_t;
            p = p + d * t;
            if (p.z < 0.f || p.z > slab.depth) break;  // left the slab
            p.x = wrap(p.x);
            p.y = wrap(p.y);
            samples.push_back({p, -d, Color3(power / slab.sigma_t), 1.f, bounce == 0});
            power *= slab.albedo;
            d = uniform_sphere(rng.next_1d(), rng.next_1d());
        }
    }
    return samples;
}

// The column point at the depth of ray(t): the field is looked up there (the slab is 1-D).
Point3f column_point(const Ray& ray, float t) { return {0.f, 0.f, ray.o.z + ray.d.z * t}; }

// The caller's bins along a view ray from the slab's top face down through it (d.z < 0): one bin
// per field leaf the depth crosses, with the renderer's own coefficients and the field's estimates
// for this ray direction. The last bin ends where the ray leaves the slab.
std::vector<DistanceBin> make_bins(const GuidingField& field, const Slab& slab, const Ray& ray,
                                   const PhaseVmm& phase_vmm) {
    const float cos_down = -ray.d.z, exit_t = slab.depth / cos_down;
    const Ray column(Point3f(0.f, 0.f, slab.depth), Vec3f(0.f, 0.f, -1.f));
    std::vector<DistanceBin> bins;
    field.tree().traverse(column, 0.f, slab.depth, [&](int leaf, float u0, float u1) {
        DistanceBin bin;
        bin.t0 = u0 / cos_down;
        bin.t1 = u1 / cos_down;
        bin.sigma_t = Color3(slab.sigma_t);
        bin.albedo = slab.albedo;
        const GuidingLeaf& l = field.leaves()[size_t(leaf)];
        bin.valid = l.valid;
        bin.inscattered = GuidingField::inscattered(l, ray.d, phase_vmm, InscatterMode::Exact).average();
        bin.L = GuidingField::incident(l, ray.d).average();
        bins.push_back(bin);
        return true;
    });
    bins.front().t0 = 0.f;  // contiguous from the origin to the exit
    bins.back().t1 = exit_t;
    return bins;
}

// Single-scattered radiance reaching the top of the slab along -ray.d: the beam's in-scattered
// radiance E0 exp(-sigma_t z) / (4 pi) at depth z, integrated along the ray with sigma_s and the
// transmittance back to the origin. Closed form: z(t) = D - t c, c = -d.z.
float beam_inscattered(const Slab& slab, float z) { return slab.E0 * std::exp(-slab.sigma_t * z) / (4.f * kPi); }
double single_scatter_exact(const Slab& slab, float cos_down) {
    const double s = slab.depth / cos_down, k = slab.sigma_t * (1.0 - cos_down);
    return slab.sigma_s() * slab.E0 / (4.0 * kPi) * std::exp(-double(slab.sigma_t) * slab.depth) *
           (k > 0 ? (1.0 - std::exp(-k * s)) / k : s);
}

int failures = 0;
void check(bool ok, const std::string& what) {
    std::printf("%s  %s\n", ok ? "ok  " : "FAIL", what.c_str());
    failures += ok ? 0 : 1;
}

struct Mean {
    double sum = 0, sum2 = 0;
    long n = 0;
    void add(double x) { sum += x; sum2 += x * x; ++n; }
    double mean() const { return sum / double(n); }
    double variance() const { return std::max(0.0, sum2 / double(n) - mean() * mean()); }
    double standard_error() const { return std::sqrt(variance() / double(n)); }
};

void check_unbiased(const Mean& m, double exact, const char* name) {
    const double z = (m.mean() - exact) / std::max(m.standard_error(), 1e-12);
    char line[256];
    std::snprintf(line, sizeof line, "%s: %.6g +- %.2g (exact %.6g, z = %.2f, variance %.3g)", name, m.mean(),
                  m.standard_error(), exact, z, m.variance());
    check(std::abs(z) < 5.0, line);
}

// Save, load, and the loaded field is the same field (byte for byte).
GuidingField save_and_load(const GuidingField& field, const std::filesystem::path& dir) {
    const std::string path = (dir / "slab_embed.vgfield").string();
    save_field(path, field);
    GuidingField loaded = load_field(path);
    check(serialize_field(loaded) == serialize_field(field),
          "save_field / load_field round trip (" + std::to_string(loaded.leaves().size()) + " leaves, " + path + ")");
    return loaded;
}

// The density the sampler reports integrates with the surface probability to one (midpoint rule).
void check_normalised(const std::vector<DistanceBin>& bins, const GuidedDistanceSettings& settings) {
    double total = incremental_surface_probability(bins, settings);
    const TabulatedDistance tab(bins, 0.f, settings);
    double total_tab = tab.surface_probability();
    for (const DistanceBin& b : bins) {
        const int steps = 400;
        const double h = (b.t1 - b.t0) / steps;
        for (int i = 0; i < steps; ++i) {
            const float t = float(b.t0 + (i + 0.5) * h);
            total += incremental_distance_pdf(bins, t, settings) * h;
            total_tab += tab.pdf(t) * h;
        }
    }
    char line[160];
    std::snprintf(line, sizeof line, "distance pdf + P_surf integrate to one: incremental %.5f, tabulated %.5f",
                  total, total_tab);
    check(std::abs(total - 1.0) < 2e-3 && std::abs(total_tab - 1.0) < 2e-3, line);
}

// The sampler draws from the density it reports: the share of samples per bin against the pdf's mass.
void check_histogram(const std::vector<DistanceBin>& bins, const GuidedDistanceSettings& settings, Rng& rng) {
    const int n = 200000;
    std::vector<long> count(bins.size() + 1, 0);  // the last entry: surface events
    for (int i = 0; i < n; ++i) {
        size_t k = 0;
        auto next = [&](DistanceBin& b) { return k < bins.size() ? (b = bins[k++], true) : false; };
        const DistanceSample s = sample_incremental_distance(next, rng, settings);
        if (s.event == DistanceEvent::Surface) {
            ++count.back();
            continue;
        }
        size_t bin = 0;
        while (bin + 1 < bins.size() && s.t >= bins[bin].t1) ++bin;
        ++count[bin];
    }
    double worst = 0;
    for (size_t k = 0; k <= bins.size(); ++k) {
        double mass = incremental_surface_probability(bins, settings);
        if (k < bins.size()) {
            mass = 0;
            const int steps = 200;
            const double h = (bins[k].t1 - bins[k].t0) / steps;
            for (int i = 0; i < steps; ++i)
                mass += incremental_distance_pdf(bins, float(bins[k].t0 + (i + 0.5) * h), settings) * h;
        }
        const double sd = std::sqrt(std::max(mass * (1 - mass), 1e-8) / n);
        worst = std::max(worst, std::abs(double(count[k]) / n - mass) / sd);
    }
    char line[160];
    std::snprintf(line, sizeof line, "sampled bin frequencies match the pdf's bin masses (%zu bins, worst |z| = %.2f)",
                  bins.size() + 1, worst);
    check(worst < 5.0, line);
}

// Guided distance sampling of the single-scattered radiance along `ray`: at a medium event t the
// weight is T(0, t) sigma_s / pdf with the renderer's exact transmittance and coefficient (never
// the bins' proxies), times the beam's in-scattered radiance there; a surface event sees nothing
// (the beam is collimated and the ray does not look into it).
void estimate_single_scatter(const Slab& slab, const Ray& ray, const std::vector<DistanceBin>& bins,
                             const GuidedDistanceSettings& settings, Rng& rng, Mean& out) {
    size_t k = 0;
    auto next = [&](DistanceBin& b) { return k < bins.size() ? (b = bins[k++], true) : false; };
    const DistanceSample s = sample_incremental_distance(next, rng, settings);
    if (s.event == DistanceEvent::Surface) return out.add(0.0);
    const float weight = std::exp(-slab.sigma_t * s.t) * slab.sigma_s() / s.pdf;
    out.add(weight * beam_inscattered(slab, ray.o.z + ray.d.z * s.t));
}

// The same with the continuation decision at the scattering vertex: E[X] = w <L~_i> (the field's
// estimate of what the continuation collects) against the pixel's estimate I~ = the bins' own sum
// of T~ alpha (1 - T~) L~_i. n = floor(q + u) continuations, each with weight w / q; a
// continuation estimates the beam's transmittance to depth z by one free flight (1 if it gets
// through), a random estimate, so that splitting has something to average. rrs = null: always one
// continuation (the baseline).
void estimate_with_rrs(const Slab& slab, const Ray& ray, const std::vector<DistanceBin>& bins,
                       const GuidedDistanceSettings& settings, const RouletteSplitting* rrs, const GuidingField& field,
                       const PhaseVmm& phase_vmm, float pixel_estimate, Rng& rng, Mean& out, Mean& branches) {
    size_t k = 0;
    auto next = [&](DistanceBin& b) { return k < bins.size() ? (b = bins[k++], true) : false; };
    const DistanceSample s = sample_incremental_distance(next, rng, settings);
    if (s.event == DistanceEvent::Surface) {
        branches.add(1);
        return out.add(0.0);
    }
    const Color3 w(std::exp(-slab.sigma_t * s.t) * slab.sigma_s() / s.pdf);
    const float z = ray.o.z + ray.d.z * s.t;
    const Color3 psi = field.inscattered(column_point(ray, s.t), ray.d, phase_vmm);
    const float q = rrs ? rrs->factor(w, psi, pixel_estimate, 1) : 1.f;
    const int n = stochastic_round(q, rng.next_1d());
    if (rrs) rrs->count_outcome(n);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const bool through = -std::log(1.f - rng.next_1d()) / slab.sigma_t > z;
        sum += w.r / q * (through ? slab.E0 / (4.f * kPi) : 0.f);
    }
    branches.add(std::max(n, 1));
    out.add(sum);
}

float pixel_estimate_from_bins(const std::vector<DistanceBin>& bins) {
    float I = 0.f, tau = 0.f;
    for (const DistanceBin& b : bins) {
        const float bin_tau = b.sigma_t.average() * (b.t1 - b.t0);
        I += std::exp(-tau) * b.albedo * (1.f - std::exp(-bin_tau)) * b.inscattered;
        tau += bin_tau;
    }
    return I;
}

// The guided direction sampler at a vertex: E[f_p / p] = integral of f_p = 1 for any guide.
void check_direction(const GuidingField& field, const Slab& slab, Rng& rng) {
    const IsotropicPhase phase;
    const PhaseVmm phase_vmm = hg_phase_vmm(0.f);
    const GuidingLeaf* leaf = field.leaf_at(Point3f(0.f, 0.f, 0.3f * slab.depth));
    const GuidedDirectionSampler sampler(DirectionGuiding::Product, leaf, phase, Vec3f(0.f, 0.f, -1.f), 0.5f,
                                         &phase_vmm);
    Mean m;
    int guided = 0;
    for (int i = 0; i < 100000; ++i) {
        const Point2f u(rng.next_1d(), rng.next_1d());
        const GuidedDirectionSampler::Sample s = sampler.sample(u, rng.next_1d());
        m.add(s.weight);
        guided += s.guided ? 1 : 0;
    }
    char line[200];
    std::snprintf(line, sizeof line, "guided direction sampler (product, %d%% from the guide): E[f_p/p] = %.4f +- %.4f",
                  guided / 1000, m.mean(), m.standard_error());
    check(sampler.guided() && std::abs(m.mean() - 1.0) < 5 * m.standard_error() + 1e-4, line);
}

}  // namespace

int main(int argc, char** argv) {
    const std::filesystem::path dir = argc > 1 ? argv[1] : std::filesystem::temp_directory_path().string();
    const Slab slab;
    Rng rng{0x5eed};

    // 1. A field from the renderer's own samples, then saved and loaded.
    const std::vector<RadianceSample> samples = trace_photons(slab, 40000, rng);
    GuidingFieldSettings field_settings;
    field_settings.fluence = FluenceEstimator::PerVolume;
    const GuidingField trained = GuidingField::build(slab.column(), samples, field_settings);
    std::printf("field: %zu photon collisions, %d leaves\n", samples.size(), trained.tree().leaf_count());
    const GuidingField field = save_and_load(trained, dir);

    // 2. Guided distance sampling on view rays entering the top face at 20 and 50 degrees.
    const PhaseVmm phase_vmm = hg_phase_vmm(0.f);  // the phase VMM of the isotropic phase function
    GuidedDistanceSettings settings;               // defaults: c_T = 0.5, p_max = 0.9, Vre
    GuidedDistanceSettings free_flight = settings;
    free_flight.c_T = 1.f;  // transmittance sampling only, for comparison
    for (float degrees : {20.f, 50.f}) {
        const float theta = degrees * kPi / 180.f;
        const Ray ray(Point3f(0.f, 0.f, slab.depth), Vec3f(std::sin(theta), 0.f, -std::cos(theta)));
        const std::vector<DistanceBin> bins = make_bins(field, slab, ray, phase_vmm);
        std::printf("view ray at %.0f degrees: %zu bins\n", degrees, bins.size());
        check_normalised(bins, settings);
        check_histogram(bins, settings, rng);

        const double exact = single_scatter_exact(slab, std::cos(theta));
        Mean guided, unguided;
        for (int i = 0; i < 200000; ++i) {
            estimate_single_scatter(slab, ray, bins, settings, rng, guided);
            estimate_single_scatter(slab, ray, bins, free_flight, rng, unguided);
        }
        check_unbiased(guided, exact, "guided distance sampling");
        check_unbiased(unguided, exact, "free-flight sampling   ");

        // 3. The continuation decision: guided RR and splitting with the paper's q = E[X] / I
        // (window s = 1; volguide's default is the ADRRS window s = 5, which decides less often).
        RouletteSplittingSettings rrs_settings;
        rrs_settings.mode = RouletteMode::GuidedSplitting;
        rrs_settings.window = 1.f;
        const RouletteSplitting rrs(rrs_settings);
        const float pixel = pixel_estimate_from_bins(bins);
        Mean with_rrs, without_rrs, branches, one_branch;
        for (int i = 0; i < 200000; ++i) {
            estimate_with_rrs(slab, ray, bins, settings, &rrs, field, phase_vmm, pixel, rng, with_rrs, branches);
            estimate_with_rrs(slab, ray, bins, settings, nullptr, field, phase_vmm, pixel, rng, without_rrs, one_branch);
        }
        const RouletteSplittingStats st = rrs.stats();
        std::printf("      RR/splitting: pixel estimate from the field %.4g, %llu kills, %llu splits, %.3f branches per sample\n",
                    pixel, (unsigned long long)st.kills, (unsigned long long)st.splits, branches.mean());
        check_unbiased(without_rrs, exact, "one continuation       ");
        check_unbiased(with_rrs, exact, "guided RR/splitting    ");
    }

    // 4. The direction decision at a vertex in the slab.
    check_direction(field, slab, rng);

    std::printf("%s\n", failures ? "FAILED" : "all checks passed");
    return failures ? 1 : 0;
}
