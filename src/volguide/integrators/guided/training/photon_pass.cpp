#include "volguide/integrators/guided/training/photon_pass.h"

#include <tbb/enumerable_thread_specific.h>

#include <chrono>
#include <mutex>

#include "volguide/core/parallel.h"
#include "volguide/integrators/guided/training/emission_focus.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/volume_nee.h"
#include "volguide/media/medium.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {

// A random-number stream no camera pixel uses (pixel indices are y * width + x).
constexpr uint64_t kPhotonStream = 0xF07F07F0ull;
constexpr uint64_t kPilotStream = 0xF07F07F1ull;
constexpr int64_t kBatch = 4096;
// Batches per wave (the deposit cap is checked between waves): a constant, not the thread count.
constexpr int64_t kWaveBatches = 16;

struct BatchResult {
    std::vector<RadianceSample> samples;
    int64_t collisions = 0;
    int64_t depositing = 0;  // photons that deposited at least once
};

// The media photons start in, per emitter. A shape that separates media, or a light that names its
// medium, says where; a lamp inside fog whose shape names no medium (Mitsuba's scenes often do that:
// the camera's walk never needs it) is in the medium that encloses it (medium_enclosing), probed once
// at 16 points it emits from -- per photon only if they disagree (a light straddling a boundary).
// Started in vacuum instead, such a lamp's photons left every collision of its direct light out of
// the field (fogbox's in-scattered estimate read about half the path-traced one: see
// docs/guiding-estimates.md). Training only: the render's estimate never reads it.
class StartMedia {
public:
    explicit StartMedia(const Scene& scene) : ambient_(ambient_medium(scene)) {
        for (const auto& e : scene.emitters()) starts_.push_back(resolve(scene, *e));
    }

    const Medium* at(const Scene& scene, size_t emitter_index, const Emitter& emitter, const RaySample& rs) const {
        const Start& st = starts_[emitter_index];
        switch (st.kind) {
            case Kind::Outside: return nullptr;
            case Kind::Shape: return emitter.shape()->target_medium(rs.n, rs.ray.d);
            case Kind::Fixed: return st.medium;
            case Kind::Probe: break;
        }
        // A light straddling a boundary: each photon's origin decides (its direction does not).
        return medium_enclosing(scene, rs.ray.o, ambient_);
    }

private:
    enum class Kind { Outside, Shape, Fixed, Probe };
    struct Start {
        Kind kind = Kind::Outside;
        const Medium* medium = nullptr;
    };

    Start resolve(const Scene& scene, const Emitter& emitter) const {
        if (emitter.is_infinite() || (emitter.flags() & emitter_flags::DeltaDirection)) return {};  // from outside
        if (const Shape* shape = emitter.shape(); shape && is_medium_transition(*shape)) return {Kind::Shape, nullptr};
        if (!emitter.shape() && emitter.medium()) return {Kind::Fixed, emitter.medium()};
        const Medium* found = nullptr;
        constexpr int kProbes = 16;
        for (int i = 0; i < kProbes; ++i) {
            const Point2f u_pos((float(i % 4) + 0.5f) / 4.f, (float(i / 4) + 0.5f) / 4.f);
            const RaySample rs = emitter.sample_ray(u_pos, Point2f(0.5f, 0.5f));
            const Medium* m = medium_enclosing(scene, rs.ray.o, ambient_);
            if (i > 0 && m != found) return {Kind::Probe, nullptr};
            found = m;
        }
        return {Kind::Fixed, found};
    }

    const Medium* ambient_;
    std::vector<Start> starts_;
};

// An emitted photon: its ray, the medium it starts in and its flux.
struct Photon {
    Ray ray;
    const Medium* medium;
    Color3 flux;
};

// Carries one emitted photon through the scene, depositing its medium collisions in `out`.
void transport(const Scene& scene, const PhotonPassSettings& s, const Photon& photon, Sampler& sampler,
               BatchResult& out) {
    Ray ray = photon.ray;
    const Medium* medium = photon.medium;
    const Color3& flux = photon.flux;
    Color3 throughput(1.f);
    const BSDFContext ctx{TransportMode::Importance};
    int depth = 0, null_crossings = 0;
    while (true) {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) si = miss_interaction(ray);
        if (medium) {
            const FreeFlightSample ff =
                medium->sample_free_flight(ray, si.is_valid() ? si.t : ray.tmax, throughput, sampler);
            if (ff.scattered) {
                ++out.collisions;
                // Flux arriving at the collision over sigma_t, before the albedo (docs/theory.md §5.2).
                const Color3 deposit = flux * throughput * ff.flight_weight;
                // depth 0: straight from the emitter (null boundaries crossed do not count).
                if (deposit.is_finite() && !deposit.is_black())
                    out.samples.push_back({ff.mi.p, -ray.d, deposit, 1.f, depth == 0});
                throughput *= ff.weight;
                ++depth;
                if (throughput.is_black() || (s.max_depth >= 0 && depth >= s.max_depth)) return;
                if (depth > s.rr_depth) {
                    // Russian roulette on the throughput relative to the photon's own flux.
                    const float q = std::min(throughput.max_value(), 0.95f);
                    if (!(sampler.next_1d() < q)) return;
                    throughput *= 1.f / q;
                }
                const Medium& m = ff.mi.medium ? *ff.mi.medium : *medium;
                const PhaseSample ps = m.phase().sample(ff.mi.wi, sampler.next_2d());
                if (!(ps.pdf > 0.f)) return;
                throughput *= ps.weight;
                ray = ff.mi.spawn_ray(ps.wo);
                continue;
            }
            throughput *= ff.weight;
            if (throughput.is_black()) return;
        }
        if (!si.is_valid()) return;
        const BSDF& bsdf = *si.shape->bsdf();
        auto [bs, weight] = bsdf.sample(ctx, si, sampler.next_1d(), sampler.next_2d());
        throughput *= weight;
        if (throughput.is_black() || !throughput.is_finite()) return;
        if (bs.sampled_flags & bsdf_flags::Null) {
            if (++null_crossings > kMaxNullCrossings) return;
        } else {
            if (s.max_depth >= 0 && ++depth >= s.max_depth) return;
            if (depth > s.rr_depth) {
                const float q = std::min(throughput.max_value(), 0.95f);
                if (!(sampler.next_1d() < q)) return;
                throughput *= 1.f / q;
            }
        }
        const Vec3f wo = si.to_world(bs.wo);
        medium = medium_after(si, wo, medium);
        ray = si.spawn_ray(wo);
    }
}

// Where photons start: the emitters' media and the emission focus.
struct Emission {
    const StartMedia& media;
    const EmissionFocus& focus;
};

// One photon: an emitter by power, its emission sample (focused when the focus is active), then
// transport. With `pilot`, the emission sample is recorded with whether the photon deposited.
void trace_one(const Scene& scene, const PhotonPassSettings& s, const Emission& emission, Sampler& sampler,
               BatchResult& out, EmissionPilot* pilot) {
    const EmissionFocus& focus = emission.focus;
    auto [index, p_emitter] = scene.sample_emitter_index_for_emission(sampler.next_1d());
    if (!(p_emitter > 0.f)) return;
    const Emitter& emitter = *scene.emitters()[index];
    Point2f u_pos = sampler.next_2d(), u_dir = sampler.next_2d();
    Point2f& u_focused = focused_sample(emitter) == FocusedSample::Position ? u_pos : u_dir;
    float focus_weight = 1.f;
    if (focus.active()) focus_weight = focus.warp(index, sampler.next_1d(), u_focused);
    const size_t deposits_before = out.samples.size();
    const RaySample rs = emitter.sample_ray(u_pos, u_dir);
    if (!rs.weight.is_black() && rs.weight.is_finite())
        transport(scene, s, Photon{rs.ray, emission.media.at(scene, index, emitter, rs), rs.weight * (focus_weight / p_emitter)},
                  sampler, out);
    const bool deposited = out.samples.size() > deposits_before;
    out.depositing += deposited;
    if (pilot) pilot->record(index, u_focused, deposited);
}

// The pilot of the focused emission: photons from their own stream, uniform emission, deposits
// discarded. Integer counts summed over threads: the same focus for any thread count.
EmissionFocus focus_emission(const Scene& scene, const PhotonPassSettings& s, const StartMedia& media,
                             int64_t pilot_photons, const PreprocessContext& context) {
    tbb::enumerable_thread_specific<EmissionPilot> pilots(
        [&] { return EmissionPilot(scene.emitters().size()); });
    const EmissionFocus uniform;
    const int64_t batches = (pilot_photons + kBatch - 1) / kBatch;
    parallel_for(int64_t(0), batches, [&](int64_t b) {
        if (context.cancelled()) return;
        EmissionPilot& pilot = pilots.local();
        BatchResult scratch;
        for (int64_t i = b * kBatch; i < std::min(pilot_photons, (b + 1) * kBatch); ++i) {
            Sampler sampler(context.seed, kPilotStream, uint64_t(i));
            trace_one(scene, s, Emission{media, uniform}, sampler, scratch, &pilot);
            scratch.samples.clear();
        }
    });
    EmissionPilot total(scene.emitters().size());
    for (const EmissionPilot& p : pilots) total += p;
    return EmissionFocus(total, s.focus_defensive);
}

}  // namespace

PhotonPassResult trace_photons(const Scene& scene, const PhotonPassSettings& settings,
                               const PreprocessContext& context) {
    PhotonPassResult result;
    const auto start = std::chrono::steady_clock::now();  // the pilot counts against time_limit
    const StartMedia media(scene);
    EmissionFocus focus;
    if (settings.focus && settings.photons > 0 && !scene.emitters().empty()) {
        result.pilot_photons = settings.pilot_photons > 0
                                   ? settings.pilot_photons
                                   : std::min<int64_t>(settings.photons / 8 + 1, int64_t(1) << 20);
        focus = focus_emission(scene, settings, media, result.pilot_photons, context);
    }
    const int64_t batches = (settings.photons + kBatch - 1) / kBatch;
    std::vector<BatchResult> per_batch(size_t(std::max<int64_t>(batches, 0)));
    std::vector<uint8_t> done(per_batch.size(), 0);
    std::mutex progress_mutex;
    std::atomic<int64_t> finished{0};
    // Waves of batches: every batch of a wave completes (unless cancelled or out of time) before the
    // deposit cap is checked, so the batches kept do not depend on the thread count.
    int64_t deposits = 0;
    for (int64_t wave = 0; wave < batches; wave += kWaveBatches) {
        if (settings.max_deposits > 0 && deposits >= settings.max_deposits) {
            result.deposit_limited = true;
            break;
        }
        const int64_t wave_end = std::min(batches, wave + kWaveBatches);
        parallel_for(wave, wave_end, [&](int64_t b) {
            if (context.cancelled()) return;
            if (settings.time_limit > 0 &&
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
                    settings.time_limit)
                return;
            const int64_t first = b * kBatch, last = std::min(settings.photons, first + kBatch);
            BatchResult& out = per_batch[size_t(b)];
            for (int64_t i = first; i < last; ++i) {
                Sampler sampler(context.seed, kPhotonStream, uint64_t(settings.first_photon + i));
                trace_one(scene, settings, Emission{media, focus}, sampler, out, nullptr);
            }
            done[size_t(b)] = 1;
            const int64_t n = ++finished;
            if (context.progress) {
                std::lock_guard lock(progress_mutex);
                Progress p;
                p.phase = "photons";
                p.fraction = double(n) / double(batches);
                p.elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                context.progress(p);
            }
        });
        for (int64_t b = wave; b < wave_end; ++b) deposits += int64_t(per_batch[size_t(b)].samples.size());
        if (context.cancelled()) break;
    }
    // Join completed batches in photon order; a cancelled pass keeps what it traced.
    for (size_t b = 0; b < per_batch.size(); ++b) {
        if (!done[b]) continue;
        result.photons_traced += std::min(settings.photons, int64_t(b + 1) * kBatch) - int64_t(b) * kBatch;
        result.collisions += per_batch[b].collisions;
        result.photons_depositing += per_batch[b].depositing;
        result.samples.insert(result.samples.end(), per_batch[b].samples.begin(), per_batch[b].samples.end());
    }
    const float inv_n = result.photons_traced > 0 ? 1.f / float(result.photons_traced) : 0.f;
    for (RadianceSample& s : result.samples) s.weight *= inv_n;
    return result;
}

}  // namespace volguide
