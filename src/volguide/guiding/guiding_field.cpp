#include "volguide/guiding/guiding_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/parallel.h"

namespace volguide {

namespace {

double box_volume(const BBox3f& b) {
    const Vec3f e = b.extents();
    return double(e.x) * double(e.y) * double(e.z);
}

GuidingLeaf fit_leaf(std::span<const RadianceSample> samples, std::span<const uint32_t> indices,
                     const BBox3f& box, const GuidingFieldSettings& settings) {
    GuidingLeaf leaf;
    leaf.samples = uint32_t(indices.size());
    std::vector<DirectionalSample> directions, indirect;
    directions.reserve(indices.size());
    bool any_direct = false;
    double sum[3] = {0, 0, 0}, count = 0;
    for (uint32_t i : indices) {
        const RadianceSample& s = samples[i];
        count += double(s.count);
        if (!s.weight.is_finite()) continue;
        for (int c = 0; c < 3; ++c) sum[c] += double(s.weight[c]);
        // One directional shape for the three channels, weighted by the channel average.
        const float w = s.weight.average();
        if (w > 0.f) {
            directions.push_back({s.direction, w});
            if (s.direct)
                any_direct = true;
            else
                indirect.push_back({s.direction, w});
        }
    }
    const double norm =
        settings.fluence == FluenceEstimator::PerVolume ? box_volume(box) : std::max(count, 1.0);
    if (norm > 0.0) leaf.fluence = Color3(float(sum[0] / norm), float(sum[1] / norm), float(sum[2] / norm));
    VmmFitSettings fit = settings.fit;
    fit.initial_lobes = settings.lobes;
    if (int(directions.size()) >= settings.min_samples) {
        fit_vmm(leaf.vmm, directions, fit);
        leaf.valid = leaf.vmm.size() > 0;
    }
    if (!any_direct) {
        leaf.vmm_indirect = leaf.vmm;
        leaf.valid_indirect = leaf.valid;
    } else if (int(indirect.size()) >= settings.min_samples) {
        fit_vmm(leaf.vmm_indirect, indirect, fit);
        leaf.valid_indirect = leaf.vmm_indirect.size() > 0;
    }
    return leaf;
}

}  // namespace

GuidingField GuidingField::build(const BBox3f& bounds, std::span<const RadianceSample> samples,
                                 const GuidingFieldSettings& settings) {
    if (settings.lobes < 1 || settings.lobes > kVmmMaxLobes)
        throw std::invalid_argument("guiding field: lobes must be in [1, " + std::to_string(kVmmMaxLobes) +
                                    "]");
    std::vector<Point3f> positions(samples.size());
    // Only samples that carry radiance drive the subdivision (spatial_tree.h): zero-valued training
    // samples still count in their leaf's fluence mean. Photon samples are all positive.
    std::vector<uint8_t> carries_radiance(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        positions[i] = samples[i].position;
        carries_radiance[i] = samples[i].weight.is_finite() && samples[i].weight.average() > 0.f;
    }
    SpatialTree tree = SpatialTree::build(bounds, positions, settings.tree, carries_radiance);
    std::vector<GuidingLeaf> leaves(size_t(tree.leaf_count()));
    parallel_for(0, tree.leaf_count(), [&](int l) {
        leaves[size_t(l)] = fit_leaf(samples, tree.leaf_samples(l), tree.leaf_bounds(l), settings);
    });
    return GuidingField(std::move(tree), std::move(leaves));
}

GuidingField::GuidingField(SpatialTree tree, std::vector<GuidingLeaf> leaves)
    : tree_(std::move(tree)), leaves_(std::move(leaves)) {
    if (int(leaves_.size()) != tree_.leaf_count())
        throw std::invalid_argument("guiding field: leaf count does not match the tree");
}

void GuidingField::set_medium_fractions(std::span<const float> fractions, bool scale_fluence) {
    if (fractions.size() != leaves_.size())
        throw std::invalid_argument("guiding field: one medium fraction per leaf expected");
    for (size_t l = 0; l < leaves_.size(); ++l) {
        const float f = std::clamp(fractions[l], 0.f, 1.f);
        leaves_[l].medium_fraction = f;
        // A fraction measured as 0 in a leaf that did receive collisions is a sliver the measurement
        // missed: leave that leaf unscaled rather than divide by 0.
        if (scale_fluence && f > 0.f) leaves_[l].fluence = leaves_[l].fluence * (1.f / f);
    }
}

Color3 GuidingField::incident(const GuidingLeaf& leaf, const Vec3f& w) {
    if (!leaf.valid) return Color3(0.f);
    return leaf.fluence * leaf.vmm.eval(w);
}

Color3 GuidingField::inscattered(const GuidingLeaf& leaf, const Vec3f& w, const PhaseVmm& phase,
                                 InscatterMode mode) {
    if (!leaf.valid) return Color3(0.f);
    const float value = mode == InscatterMode::Exact ? float(convolve_exact(leaf.vmm, phase, w))
                                                     : convolve(leaf.vmm, phase).eval(w);
    return leaf.fluence * value;
}

Color3 GuidingField::incident(const Point3f& x, const Vec3f& w) const {
    const GuidingLeaf* leaf = leaf_at(x);
    return leaf ? incident(*leaf, w) : Color3(0.f);
}

Color3 GuidingField::inscattered(const Point3f& x, const Vec3f& w, const PhaseVmm& phase,
                                 InscatterMode mode) const {
    const GuidingLeaf* leaf = leaf_at(x);
    return leaf ? inscattered(*leaf, w, phase, mode) : Color3(0.f);
}

}  // namespace volguide
