#pragma once
// A training file (`volguide train -o FILE`, read by `volguide render --field FILE`): an
// integrator's pre-pass (Integrator::prepass_state, e.g. guided_volpath's field and pixel
// estimate) with what it belongs to, so that a render with another scene or another integrator
// configuration is refused instead of silently using the wrong field.
//
// Layout (little-endian): 8 bytes magic "VGTRAIN\0", u32 version (kTrainingFormatVersion), then
// the strings scene fingerprint, scene file, integrator configuration, each as u32 length + bytes,
// u64 training seed, u64 pre-pass length + the pre-pass bytes, u64 FNV-1a checksum of everything
// between the magic and the checksum. Saving is atomic (temporary file + rename).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace volguide {

inline constexpr uint32_t kTrainingFormatVersion = 1;

class TrainingFileError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

struct TrainingFile {
    std::string scene;       // scene_fingerprint() of the scene it was trained on
    std::string scene_file;  // that scene's path as given (for messages only)
    std::string integrator;  // Integrator::configuration()
    uint64_t seed = 0;       // the training seed
    std::string prepass;     // Integrator::prepass_state()
};

std::string serialize_training(const TrainingFile& file);
TrainingFile deserialize_training(const std::string& bytes);  // throws TrainingFileError

// File variants; errors name the file.
void save_training(const std::string& path, const TrainingFile& file);
TrainingFile load_training(const std::string& path);

// The fingerprint of a pre-pass (what rendered parts record as their field): equal bytes, equal
// fingerprints, whether the pre-pass was trained in the render or loaded with --field.
std::string prepass_fingerprint(const std::string& prepass);

// "" when the training file belongs to this scene and integrator configuration, otherwise the
// reason, naming which of the two differs (the configuration is checked first: the scene's
// fingerprint covers the whole scene file, its <integrator> included).
std::string training_mismatch(const TrainingFile& file, const std::string& scene_fingerprint,
                              const std::string& integrator_configuration);

}  // namespace volguide
