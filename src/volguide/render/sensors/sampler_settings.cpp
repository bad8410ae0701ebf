#include "volguide/render/sensors/sampler_settings.h"

#include <cmath>

#include "volguide/core/log.h"

namespace volguide {

SamplerSettings::SamplerSettings(const Properties& props) {
    const std::string& type = props.type();
    const bool known = type == "independent" || type == "stratified" || type == "multijitter" ||
                       type == "orthogonal" || type == "ldsampler";
    if (!known)
        props.fail_here("unsupported sampler plugin '{}' (supported: independent; stratified, multijitter, "
                        "orthogonal, ldsampler are sampled independently)",
                        type);
    int64_t count = props.get_int("sample_count", 4);
    if (count <= 0 || count > (int64_t(1) << 30))
        props.fail_at("sample_count", "sample_count must be in [1, 2^30], got {}", count);
    int64_t s = props.get_int("seed", 0);
    if (s < 0) props.fail_at("seed", "seed must be >= 0, got {}", s);
    seed = uint64_t(s);

    if (type != "independent") {
        // Mitsuba rounds these sample counts: stratified to a square, ldsampler to a power of two.
        if (type == "stratified") {
            int64_t res = int64_t(std::ceil(std::sqrt(double(count))));
            count = res * res;
        } else if (type == "ldsampler") {
            int64_t p = 1;
            while (p < count) p *= 2;
            count = p;
        }
        props.mark_used("jitter");    // stratified, multijitter, orthogonal
        props.mark_used("strength");  // orthogonal
        warn(props.location(), "sampler '{}' is sampled independently ({} samples per pixel)", type, count);
    }
    sample_count = int(count);
}

std::string SamplerSettings::to_string() const {
    return fmt::format("independent[sample_count={}, seed={}]", sample_count, seed);
}

}  // namespace volguide
