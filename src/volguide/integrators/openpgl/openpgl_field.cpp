#include "volguide/integrators/openpgl/openpgl_field.h"

#include <algorithm>

namespace volguide {

namespace {

// Open PGL's 8-wide device needs AVX2; the 4-wide one runs on SSE4.
PGL_DEVICE_TYPE device_type() {
    return __builtin_cpu_supports("avx2") ? PGL_DEVICE_TYPE_CPU_8 : PGL_DEVICE_TYPE_CPU_4;
}

}  // namespace

OpenPglField::OpenPglField(const BBox3f& bounds, int threads, int max_samples_per_leaf)
    : device_(std::make_unique<openpgl::cpp::Device>(device_type(), size_t(std::max(threads, 1)))) {
    // deterministic = true: regions sort their samples before fitting and use integer sample
    // statistics, so the field does not depend on the order threads added the samples.
    config_.Init(PGL_SPATIAL_STRUCTURE_KDTREE, PGL_DIRECTIONAL_DISTRIBUTION_PARALLAX_AWARE_VMM, true,
                 size_t(max_samples_per_leaf));
    field_ = std::make_unique<openpgl::cpp::Field>(device_.get(), config_);
    // Without bounds Open PGL guesses them from the first batch, and Init fails outside them.
    pgl_box3f box;
    pglBox3f(box, bounds.lo.x, bounds.lo.y, bounds.lo.z, bounds.hi.x, bounds.hi.y, bounds.hi.z);
    field_->SetSceneBounds(box);
}

void OpenPglField::update() {
    samples_total_ += storage_.GetSizeSurface() + storage_.GetSizeVolume();
    field_->Update(storage_);
    storage_.Clear();
    ++updates_;
}

}  // namespace volguide
