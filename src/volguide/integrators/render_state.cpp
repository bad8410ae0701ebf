#include "volguide/integrators/render_state.h"

#include "volguide/core/bytes.h"

namespace volguide {

namespace {

template <typename T>
void put_values(ByteWriter& w, const std::vector<T>& values) {
    w.u64(values.size());
    for (T v : values) {
        if constexpr (sizeof(T) == 8)
            w.f64(v);
        else
            w.f32(v);
    }
}

// A count checked against the bytes left before anything is allocated (a corrupt count must not
// allocate terabytes).
template <typename T>
std::vector<T> get_values(ByteReader& r, const char* field) {
    const uint64_t n = r.u64(field);
    if (n > r.left() / sizeof(T)) r.fail("truncated in", field);
    std::vector<T> values(static_cast<size_t>(n));
    for (T& v : values) {
        if constexpr (sizeof(T) == 8)
            v = r.f64(field);
        else
            v = r.f32(field);
    }
    return values;
}

}  // namespace

std::string serialize_render_state(const RenderState& state) {
    ByteWriter w;
    w.u32(uint32_t(state.passes));
    w.u32(uint32_t(state.spp_done));
    w.u64(state.first_sample);
    put_values(w, state.film.weight);
    put_values(w, state.film.sum);
    put_values(w, state.film.sum2);
    put_values(w, state.noise_scale);
    w.u64(state.samples);
    w.u64(state.nonfinite_samples);
    w.u64(state.discarded_samples);
    w.bytes(state.integrator);
    return w.take();
}

RenderState deserialize_render_state(const std::string& bytes) {
    ByteReader r(bytes, "render state");
    RenderState s;
    s.passes = int(r.u32("passes"));
    s.spp_done = int(r.u32("spp done"));
    if (s.passes < 0 || s.spp_done < s.passes) r.fail("inconsistent", "passes and spp done");
    s.first_sample = r.u64("first sample");
    s.film.weight = get_values<double>(r, "film weights");
    s.film.sum = get_values<double>(r, "film sums");
    s.film.sum2 = get_values<double>(r, "film second moments");
    if (s.film.sum.size() != 3 * s.film.weight.size() || (!s.film.sum2.empty() && s.film.sum2.size() != s.film.sum.size()))
        r.fail("inconsistent", "film sums");
    s.noise_scale = get_values<float>(r, "noise scale");
    if (!s.noise_scale.empty() && s.noise_scale.size() != s.film.weight.size()) r.fail("inconsistent", "noise scale");
    s.samples = r.u64("samples");
    s.nonfinite_samples = r.u64("non-finite samples");
    s.discarded_samples = r.u64("discarded samples");
    s.integrator = r.bytes("integrator state");
    r.finish();
    return s;
}

}  // namespace volguide
