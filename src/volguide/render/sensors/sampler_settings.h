#pragma once
// The <sampler> child of a sensor. volguide draws every number from its counter-based Sampler
// (core/sampler.h), so a sampler plugin only contributes its sample count and seed. `independent`
// is Mitsuba's default; the stratified and low-discrepancy types are accepted with a warning and
// sampled independently (same expectation, different noise), with their sample count rounded as
// Mitsuba rounds it.
#include <cstdint>

#include "volguide/core/object.h"
#include "volguide/core/properties.h"

namespace volguide {

class SamplerSettings final : public Object {
public:
    SamplerSettings() = default;
    explicit SamplerSettings(const Properties& props);
    int sample_count = 4;
    uint64_t seed = 0;
    std::string to_string() const override;
};

}  // namespace volguide
