#pragma once
// A render checkpoint file (`volguide render --checkpoint FILE`, read by `--resume FILE`;
// docs/distributed.md, "Checkpoints"): a render's state after a pass (render_state.h) with what it
// belongs to, so that a resume with another scene, another build, another integrator configuration or
// other image-affecting options is refused, naming what differs, instead of silently mixing renders.
//
// Layout (little-endian): 8 bytes magic "VGCKPT\0\0", u32 version (kCheckpointFormatVersion), then the
// strings scene fingerprint, scene file, build identity, integrator configuration (u64 length + bytes
// each), u64 option count and each option's name and value, the render state's bytes, and a u64
// FNV-1a checksum of everything between the magic and the checksum. Saving writes FILE.tmp, fsyncs it,
// renames it onto FILE and fsyncs the folder: a crash leaves the old checkpoint or the new one.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "volguide/integrators/render_state.h"

namespace volguide {

inline constexpr uint32_t kCheckpointFormatVersion = 1;

class CheckpointError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// What a checkpoint must agree with to be resumed.
struct CheckpointIdentity {
    std::string scene;       // the scene's fingerprint (file bytes, included files, -D values)
    std::string scene_file;  // its path as given (for messages only)
    std::string build;       // the build identity of the program that wrote it
    std::string integrator;  // Integrator::configuration()
    // The options that change the image, by name (spp target, seed, resolution, first sample, ...).
    std::vector<std::pair<std::string, std::string>> options;
};

struct Checkpoint {
    CheckpointIdentity identity;
    RenderState state;
};

std::string serialize_checkpoint(const Checkpoint& checkpoint);
Checkpoint deserialize_checkpoint(const std::string& bytes);  // throws CheckpointError

// File variants; a failed save leaves `path` as it was. Errors say what failed (the caller names the file).
void save_checkpoint(const std::string& path, const Checkpoint& checkpoint);
Checkpoint load_checkpoint(const std::string& path);

// "" when a checkpoint of `saved` may be resumed by a render of `current`, otherwise what differs
// (the first of: build, integrator configuration, scene, options, in that order).
std::string checkpoint_mismatch(const CheckpointIdentity& saved, const CheckpointIdentity& current);

}  // namespace volguide
