#pragma once
// `volguide render --checkpoint FILE [--checkpoint-every SECONDS] [--resume FILE]` (docs/distributed.md,
// "Checkpoints"): the identity a checkpoint is written with and checked against, the checkpoint a
// render resumes from, and the writer the render loop calls after its passes and when it stops.
#include <chrono>
#include <optional>
#include <string>

#include "commands.h"
#include "volguide/integrators/checkpoint_file.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"

namespace volguide::cli {

class RenderCheckpoints {
  public:
    // `options`: the render's, complete but for the checkpoints (spp, seed, first sample, variance).
    // Throws FileError naming the checkpoint or resumed file when the integrator's state cannot be
    // saved (openpgl_volpath, light tracers), or when the resumed checkpoint is unreadable or belongs
    // to another scene, build, integrator configuration or options.
    // `xml_files`: every XML file the scene read (LoadOptions::xml_files), whose bytes the checkpoint's
    // scene fingerprint covers besides `scene_fingerprint` (the main file's and the -D values').
    RenderCheckpoints(const RenderArgs& args, const Scene& scene, const std::string& scene_fingerprint,
                      const std::vector<std::string>& xml_files, const RenderOptions& options);
    // Sets options.resume and options.checkpoint (this object must outlive the render).
    void attach(RenderOptions& options);
    // "checkpoint: FILE (N spp)" after the render, "" without --checkpoint or when none was written.
    std::string summary() const;

  private:
    void write(const std::function<RenderState()>& state, bool final);

    std::string path_;
    double every_ = 60;
    CheckpointIdentity identity_;
    std::optional<Checkpoint> resumed_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    int written_spp_ = -1;
};

}  // namespace volguide::cli
