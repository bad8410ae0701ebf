#pragma once
// What ties the files of a distributed render to their scene and integrator (docs/distributed.md):
// the scene's fingerprint, a training file checked against it and given to the integrator, and the
// fingerprint of the pre-pass a render used.
#include <map>
#include <string>

#include "volguide/integrators/integrator.h"

namespace volguide::cli {

// Loads `field` (a training file), checks that it was trained for this scene (fingerprint) and this
// integrator configuration, and hands its pre-pass to the integrator. Throws FileError naming
// `field` and saying which check failed (corrupt file, other scene, other configuration).
void use_training_file(const std::string& field, const std::string& scene_fingerprint, Integrator& integrator);

// The fingerprint of the pre-pass the integrator used ("none" without one).
std::string field_fingerprint(const Integrator& integrator);

}  // namespace volguide::cli
