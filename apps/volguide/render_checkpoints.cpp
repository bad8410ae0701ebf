#include "render_checkpoints.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "build_identity.h"
#include "volguide/core/fingerprint.h"

namespace volguide::cli {

namespace {

std::string file_bytes(const std::string& path, const char* what) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path, std::string("cannot read ") + what + " for the checkpoint's identity");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

// The --field training file's bytes (the integrator's pre-pass is not trained yet when the identity is made).
std::string file_fingerprint(const std::string& path) { return fingerprint(file_bytes(path, "the training file")); }

// The options that change the image besides the scene and integrator (their fingerprints are the
// identity's own fields): a resume with other values would render another image.
std::vector<std::pair<std::string, std::string>> image_options(const RenderArgs& args, const Scene& scene,
                                                                const RenderOptions& options) {
    const Film& film = scene.sensor().film();
    const int target = options.spp > 0 ? options.spp : (options.time_budget > 0 ? 0 : scene.sensor().sample_count());
    return {{"spp target", target > 0 ? std::to_string(target) : "none (a time budget)"},
            {"seed", std::to_string(options.seed.value_or(scene.sensor().seed()))},
            {"resolution", fmt::format("{}x{}", film.width(), film.height())},
            {"first sample", std::to_string(options.first_sample)},
            {"variance", options.variance || scene.integrator().writes_variance() ? "on" : "off"},
            {"field", args.field.empty() ? "none" : file_fingerprint(args.field)}};
}

// The main file's fingerprint extended by every XML file's path and bytes (its includes).
std::string checkpoint_scene_fingerprint(const std::string& scene_fingerprint, const std::vector<std::string>& files) {
    std::string text = scene_fingerprint;
    for (const std::string& file : files)
        text += std::string(1, '\0') + file + std::string(1, '\0') + file_bytes(file, "the scene file");
    return fingerprint(text);
}

// Why this render cannot be checkpointed ("" when it can).
std::string unsupported(const Integrator& integrator) {
    if (integrator.traces_from_emitters())
        return fmt::format("the light tracer {} has no checkpoints", integrator.configuration());
    return integrator.render_state_unsupported();
}

}  // namespace

RenderCheckpoints::RenderCheckpoints(const RenderArgs& args, const Scene& scene, const std::string& scene_fingerprint,
                                     const std::vector<std::string>& xml_files, const RenderOptions& options)
    : path_(args.checkpoint), every_(args.checkpoint_every) {
    const std::string& file = path_.empty() ? args.resume : path_;
    if (file.empty()) return;
    const std::string reason = unsupported(scene.integrator());
    if (!reason.empty()) throw FileError(file, "cannot checkpoint this render: " + reason);
    identity_ = {checkpoint_scene_fingerprint(scene_fingerprint, xml_files), args.scene, build_identity(), scene.integrator().configuration(),
                 image_options(args, scene, options)};
    if (args.resume.empty()) return;
    try {
        resumed_ = load_checkpoint(args.resume);
    } catch (const CheckpointError& e) {
        throw FileError(args.resume, e.what());
    }
    const std::string mismatch = checkpoint_mismatch(resumed_->identity, identity_);
    if (!mismatch.empty()) throw FileError(args.resume, "cannot resume this render: the checkpoint was " + mismatch);
}

void RenderCheckpoints::attach(RenderOptions& options) {
    if (resumed_) options.resume = &resumed_->state;
    if (!path_.empty())
        options.checkpoint = [this](const std::function<RenderState()>& state, bool final) { write(state, final); };
}

void RenderCheckpoints::write(const std::function<RenderState()>& state, bool final) {
    const auto now = std::chrono::steady_clock::now();
    if (!final && std::chrono::duration<double>(now - last_).count() < every_) return;
    Checkpoint checkpoint{identity_, state()};
    try {
        save_checkpoint(path_, checkpoint);
    } catch (const CheckpointError& e) {
        throw FileError(path_, e.what());
    }
    last_ = now;
    written_spp_ = checkpoint.state.spp_done;
}

std::string RenderCheckpoints::summary() const {
    if (written_spp_ < 0) return "";
    return fmt::format("checkpoint: {} ({} spp)", path_, written_spp_);
}

}  // namespace volguide::cli
