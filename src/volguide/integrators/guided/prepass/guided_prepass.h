#pragma once
// What guided_volpath's pre-pass leaves for rendering, as bytes (Integrator::prepass_state): the
// guiding field (guiding/field_io's format, with its own checksum) and, with guided RR/splitting,
// the pixel estimate's RGB image before its floor (PixelEstimate::from_image rebuilds the rest
// exactly), and the allocation (estimates/allocation.h) when there is one. Layout (little-endian): u64
// field byte count, the field bytes, u32 width, u32 height (0 x 0: no pixel estimate), width x height x 3
// f32, then optionally u64 allocation byte count and its bytes (Allocation::serialize, versioned itself;
// absent in pre-passes without one). Pre-passes of earlier versions (a learned selection, a method
// choice) are refused by the allocation's check: train again. The container that checks which scene and
// configuration it belongs to is integrators/guided/prepass/training_file.h.
#include <string>

#include "volguide/core/image.h"
#include "volguide/guiding/guiding_field.h"

namespace volguide {

struct GuidedPrepass {
    GuidingField field;
    Image pixel_estimate;  // empty: none (rrs=standard)
    std::string allocation;  // Allocation::serialize(); empty: none
};

std::string serialize_guided_prepass(const GuidingField& field, const Image& pixel_estimate,
                                     const std::string& allocation = "");
// Throws FieldFormatError (guiding/field_io.h) naming what is wrong.
GuidedPrepass deserialize_guided_prepass(const std::string& bytes);

}  // namespace volguide
