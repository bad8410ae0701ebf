#include "fuzz_targets.h"

namespace volguide::fuzz {

const std::vector<FuzzTarget>& fuzz_targets() {
    static const std::vector<FuzzTarget> targets = {
        {"scene", fuzz_scene},       {"vol", fuzz_vol},
        {"vdb", fuzz_vdb},           {"field", fuzz_field},
        {"obj", fuzz_obj},           {"ply", fuzz_ply},
        {"exr_part", fuzz_exr_part}, {"serialized", fuzz_serialized},
        {"image", fuzz_image},       {"checkpoint", fuzz_checkpoint},
    };
    return targets;
}

}  // namespace volguide::fuzz
