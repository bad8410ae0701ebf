#pragma once
// Hand-made guiding leaves for the directional sampler's tests: one lobe, and four lobes of very
// different concentrations pointing in unrelated directions (none along the test's travel axis).
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "volguide/guiding/guiding_field.h"

namespace volguide::test {

inline GuidingLeaf make_leaf(std::initializer_list<std::pair<float, VmfLobe>> lobes) {
    GuidingLeaf leaf;
    for (const auto& [w, l] : lobes) leaf.vmm.add_lobe(w, l);
    leaf.vmm.normalize_weights();
    leaf.fluence = Color3(1.f);
    leaf.samples = 1000;
    leaf.valid = true;
    return leaf;
}

inline GuidingLeaf one_lobe_leaf() {
    return make_leaf({{1.f, VmfLobe(normalize(Vec3f(0.3f, 0.5f, 0.8f)), 8.f)}});
}

inline GuidingLeaf multi_lobe_leaf() {
    return make_leaf({{0.4f, VmfLobe(normalize(Vec3f(0.2f, -0.9f, 0.1f)), 15.f)},
                      {0.3f, VmfLobe(normalize(Vec3f(-0.7f, 0.1f, 0.6f)), 40.f)},
                      {0.2f, VmfLobe(normalize(Vec3f(0.5f, 0.5f, -0.7f)), 2.f)},
                      {0.1f, VmfLobe(Vec3f(0.f, 0.f, 1.f), 0.5f)}});
}

// `n` lobes of concentrations from 0.5 to ~160 on a spiral of directions: more lobes than one
// block of vector lanes (vmm/lobe_block.h) for n > 8.
inline GuidingLeaf spiral_leaf(int n) {
    GuidingLeaf leaf;
    for (int k = 0; k < n; ++k) {
        const float z = 1.f - 2.f * (float(k) + 0.5f) / float(n), r = std::sqrt(std::max(0.f, 1.f - z * z));
        const float phi = 2.39996323f * float(k);
        leaf.vmm.add_lobe(1.f + float(k % 3), VmfLobe(normalize(Vec3f(r * std::cos(phi), r * std::sin(phi), z)),
                                                     0.5f * std::pow(1.9f, float(k % 10))));
    }
    leaf.vmm.normalize_weights();
    leaf.fluence = Color3(1.f);
    leaf.samples = 1000;
    leaf.valid = true;
    return leaf;
}

// wi of the tests' vertex (towards the previous vertex); the ray travels along -wi.
inline Vec3f test_wi() {
    return normalize(Vec3f(-0.4f, 0.3f, -0.85f));
}

}  // namespace volguide::test
