// guided_volpath's render state (Integrator::render_state): what a checkpoint keeps of what the
// render's passes changed (guided_volpath.h). The pre-pass itself is not in it: a resumed render runs
// the same preprocess() again (deterministic for its seed and sample count), then this state replaces
// what the passes had changed since; a full stage trained between passes is run again from the same
// photons and checked against the checkpoint's field.
#include <algorithm>
#include <stdexcept>

#include "volguide/core/bytes.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"

namespace volguide {

namespace {

// Bumped whenever the layout below changes (a checkpoint of another layout is refused).
constexpr uint32_t kRenderStateVersion = 2;
constexpr size_t kDepositBytes = 11 * 4;

void put_deposits(ByteWriter& w, const std::vector<RadianceSample>& deposits) {
    w.u64(deposits.size());
    for (const RadianceSample& d : deposits) {
        for (float v : {d.position.x, d.position.y, d.position.z, d.direction.x, d.direction.y, d.direction.z,
                        d.weight.r, d.weight.g, d.weight.b, d.count})
            w.f32(v);
        w.u32(d.direct ? 1u : 0u);
    }
}

std::vector<RadianceSample> get_deposits(ByteReader& r) {
    const uint64_t n = r.u64("deposit count");
    if (n > r.left() / kDepositBytes) r.fail("truncated in", "deposits");
    std::vector<RadianceSample> deposits(static_cast<size_t>(n));
    for (RadianceSample& d : deposits) {
        for (float* v : {&d.position.x, &d.position.y, &d.position.z, &d.direction.x, &d.direction.y, &d.direction.z,
                         &d.weight.r, &d.weight.g, &d.weight.b, &d.count})
            *v = r.f32("deposit");
        d.direct = r.u32("deposit") != 0;
    }
    return deposits;
}

void put_named(ByteWriter& w, const std::vector<std::pair<std::string, double>>& named) {
    w.u64(named.size());
    for (const auto& [name, value] : named) {
        w.bytes(name);
        w.f64(value);
    }
}

std::vector<std::pair<std::string, double>> get_named(ByteReader& r) {
    const uint64_t n = r.u64("statistics count");
    if (n > r.left() / 16) r.fail("truncated in", "statistics");
    std::vector<std::pair<std::string, double>> named;
    for (uint64_t i = 0; i < n; ++i) {
        std::string name = r.bytes("statistic name");
        named.emplace_back(std::move(name), r.f64("statistic value"));
    }
    return named;
}

}  // namespace

std::string GuidedVolPathIntegrator::render_state_unsupported() const {
    if (settings_.roulette.mode == RouletteMode::Ears)
        return "guided_volpath with rrs=ears keeps per-pixel learning that checkpoints do not save";
    if (settings_.refine.passes > 0)
        return "guided_volpath with refine_passes > 0 keeps a refinement that checkpoints do not save";
    return "";
}

std::string GuidedVolPathIntegrator::render_state() const {
    const std::string unsupported = render_state_unsupported();
    if (!unsupported.empty()) throw std::runtime_error(unsupported);
    ByteWriter w;
    w.u32(kRenderStateVersion);
    w.u32(uint32_t(spp_done_));
    w.u32(record_all_ ? 1u : 0u);
    w.u32(uint32_t(training_.stage));
    w.u32(uint32_t(training_.full_from));
    w.u64(uint64_t(training_.photons_traced));
    w.u64(uint64_t(training_.photon_stream_next));
    w.f64(training_.seconds);
    put_deposits(w, training_.deposits);
    // The full stage ran between passes (full_from > 0): its field is not the pre-pass's.
    w.bytes(training_.full_from > 0 ? serialize_guided_prepass(field_, Image()) : std::string());
    w.bytes(learner_ ? learner_->total().serialize() : std::string());
    w.bytes(learner_ ? learner_->pixels().serialize() : std::string());
    w.bytes(guide_ && !guide_->allocation().empty() ? guide_->allocation().serialize() : std::string());
    put_named(w, training_stats_);
    return w.take();
}

void GuidedVolPathIntegrator::restore_render_state(const std::string& bytes) {
    ByteReader r(bytes, "guided_volpath render state");
    if (r.u32("version") != kRenderStateVersion) r.fail("another version of", "the render state");
    const int spp_done = int(r.u32("spp done"));
    const bool record_all = r.u32("recording rule") != 0;
    StagedTraining training;
    const uint32_t stage = r.u32("training stage");
    if (stage > uint32_t(TrainingStage::Stopped)) r.fail("invalid", "training stage");
    training.stage = TrainingStage(stage);
    training.full_from = int(r.u32("full stage start"));
    training.photons_traced = int64_t(r.u64("photons traced"));
    training.photon_stream_next = int64_t(r.u64("photon stream position"));
    training.seconds = r.f64("training seconds");
    training.deposits = get_deposits(r);
    const std::string field = r.bytes("full field");
    const std::string statistics = r.bytes("learner statistics");
    const std::string pixels = r.bytes("learner pixel moments");
    const std::string allocation = r.bytes("allocation");
    auto named = get_named(r);
    r.finish();

    if (!field.empty()) restore_full_field(field, training.full_from);
    training_ = std::move(training);
    spp_done_ = spp_done;
    record_all_ = record_all;
    if (training_.stage == TrainingStage::Stopped) learner_.reset();
    restore_learning(statistics, pixels, allocation);
    training_stats_ = std::move(named);
}

// As train_full_field() left it, by running it again: after the same pre-pass the coarse stage's
// deposits and photon stream are the checkpointed render's, so the full stage traces the same photons
// and builds the same field and pixel estimate (deterministic for the seed, any thread count). The
// checkpoint's field must then be this one, byte for byte: a field that is not is another build's or
// another pre-pass's, refused rather than rendered with. Under a time budget the full stage stops on
// the clock, so its field is not reproducible (nor is such a render): the field trained again is used.
void GuidedVolPathIntegrator::restore_full_field(const std::string& field_bytes, int full_from) {
    if (!refining_.scene) throw std::runtime_error("guided_volpath: a render state restored before preprocess()");
    if (training_.stage != TrainingStage::Coarse)
        throw std::runtime_error("guided_volpath render state: a full stage without this render's coarse stage");
    double limit = 0.0;
    if (refining_.time_budget > 0)
        limit = std::max(1e-3, settings_.training_fraction * refining_.time_budget - training_.seconds);
    spp_done_ = full_from;
    train_full_field(limit);
    if (refining_.time_budget <= 0 && serialize_guided_prepass(field_, Image()) != field_bytes)
        throw std::runtime_error("guided_volpath render state: the full field trained again differs from the checkpoint's");
}

void GuidedVolPathIntegrator::restore_learning(const std::string& statistics, const std::string& pixels,
                                               const std::string& allocation) {
    if (!statistics.empty() != bool(learner_))
        throw std::runtime_error("guided_volpath render state: the checkpoint's learner does not match this render's");
    if (learner_) {
        learner_->set_total(CellStatistics::deserialize(statistics));
        learner_->restore_pixels(pixels);
    }
    if (allocation.empty()) return;
    if (!guide_) throw std::runtime_error("guided_volpath render state: an allocation without a guide");
    Allocation a = Allocation::deserialize(allocation);
    if (a.cells() != guide_->selection_cells())
        throw std::runtime_error("guided_volpath render state: the allocation is of another field");
    if (rrs_) rrs_->set_cost_ratio(a.continuation_cost_ratio());
    guide_->set_allocation(std::move(a));
}

}  // namespace volguide
