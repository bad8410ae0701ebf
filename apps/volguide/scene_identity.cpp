#include "scene_identity.h"

#include <fmt/format.h>

#include "commands.h"
#include "volguide/integrators/guided/prepass/training_file.h"

namespace volguide::cli {

void use_training_file(const std::string& field, const std::string& scene_fingerprint, Integrator& integrator) {
    if (!integrator.has_prepass_state())
        throw FileError(field, fmt::format("the scene's integrator {} has no pre-pass; --field needs guided_volpath",
                                           integrator.configuration()));
    TrainingFile training;
    try {
        training = load_training(field);
    } catch (const TrainingFileError& e) {
        throw FileError(field, e.what());
    }
    const std::string mismatch = training_mismatch(training, scene_fingerprint, integrator.configuration());
    if (!mismatch.empty()) throw FileError(field, mismatch);
    try {
        integrator.use_prepass_state(training.prepass);
    } catch (const std::exception& e) {
        throw FileError(field, fmt::format("corrupt pre-pass: {}", e.what()));
    }
}

std::string field_fingerprint(const Integrator& integrator) {
    return integrator.has_prepass_state() ? prepass_fingerprint(integrator.prepass_state()) : "none";
}

}  // namespace volguide::cli
