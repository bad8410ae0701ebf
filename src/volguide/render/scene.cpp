#include "volguide/render/scene.h"

#include <algorithm>
#include <cmath>

#include "volguide/geometry/instance.h"
#include "volguide/render/bsdf.h"

namespace volguide {

namespace {

template <typename T>
std::shared_ptr<T> child_as(const Properties::Entry* e, const char* what) {
    auto obj = std::dynamic_pointer_cast<T>(std::get<ObjectPtr>(e->value));
    if (!obj) fail(e->loc, "<{}> is not a {}", e->category, what);
    return obj;
}

}  // namespace

Scene::Scene(const Properties& root, std::shared_ptr<Integrator> integrator,
             const std::shared_ptr<BSDF>& default_bsdf)
    : integrator_(std::move(integrator)) {
    for (const auto* e : root.children("shape")) {
        // A shapegroup is only drawn through its instances.
        if (std::dynamic_pointer_cast<ShapeGroup>(std::get<ObjectPtr>(e->value))) continue;
        auto shape = child_as<Shape>(e, "shape");
        if (!shape->bsdf()) shape->set_bsdf(default_bsdf);
        if (const auto* instance = dynamic_cast<const Instance*>(shape.get()))
            for (const auto& inner : instance->group().shapes())
                if (!inner->bsdf()) inner->set_bsdf(default_bsdf);
        shapes_.push_back(shape);
        bbox_.expand(shape->bbox());
        if (shape->emitter_ptr()) emitters_.push_back(shape->emitter_ptr());
    }
    for (const auto* e : root.children("emitter")) {
        auto emitter = child_as<Emitter>(e, "emitter");
        if ((emitter->flags() & emitter_flags::Surface) != 0)
            fail(e->loc, "an area emitter must be nested inside a <shape>");
        if (emitter->is_infinite() && !emitter->is_delta()) {
            if (environment_) fail(e->loc, "only one environment emitter (envmap or constant) is supported");
            environment_ = emitter.get();
        }
        emitters_.push_back(emitter);
    }
    auto sensors = root.children("sensor");
    if (sensors.empty()) root.fail_here("the scene has no <sensor>");
    if (sensors.size() > 1) fail(sensors[1]->loc, "only one <sensor> per scene is supported");
    sensor_ = child_as<Sensor>(sensors[0], "sensor");

    std::vector<const Shape*> raw;
    raw.reserve(shapes_.size());
    for (const auto& s : shapes_) raw.push_back(s.get());
    accel_ = std::make_unique<Accel>(raw);
    for (const auto& e : emitters_) e->set_scene_bounds(bbox_);
    // Photon emission picks lights by power (docs/theory.md §5.2), known once the bounds are set.
    std::vector<float> powers;
    float total = 0.f;
    for (const auto& e : emitters_) {
        const float p = e->power().average();
        powers.push_back(std::isfinite(p) && p > 0.f ? p : 0.f);
        total += powers.back();
    }
    if (total > 0.f) emission_distr_ = DiscreteDistribution(powers);
}

Scene::~Scene() = default;

BBox3f guiding_bounds(const Scene& scene) {
    BBox3f b = scene.bbox();
    if (!b.valid()) return BBox3f(Point3f(-1.f), Point3f(1.f));
    // A little margin so that collisions on the bounding surfaces fall inside.
    const Vec3f margin = b.extents() * 1e-3f + Vec3f(1e-4f);
    return BBox3f(b.lo - margin, b.hi + margin);
}

std::pair<DirectionSample, Color3> Scene::sample_emitter_direction(const Interaction& ref, Point2f u,
                                                                   bool test_visibility) const {
    if (emitters_.empty()) return {DirectionSample{}, Color3(0.f)};
    // Uniform emitter choice (as Mitsuba 3); the sample's x is rescaled for reuse.
    const size_t n = emitters_.size();
    float scaled = u.x * float(n);
    size_t index = std::min(size_t(scaled), n - 1);
    u.x = std::min(scaled - float(index), OneMinusEpsilon);
    const Emitter& emitter = *emitters_[index];

    auto [ds, weight] = emitter.sample_direction(ref, u);
    if (!(ds.pdf > 0.f)) return {ds, Color3(0.f)};
    ds.emitter = &emitter;
    ds.pdf /= float(n);
    weight *= float(n);
    if (test_visibility && !weight.is_black()) {
        Ray shadow = std::isinf(ds.dist) ? ref.spawn_ray(ds.d) : ref.spawn_ray_to(ds.p);
        if (occluded(shadow)) weight = Color3(0.f);
    }
    return {ds, weight};
}

float Scene::pdf_emitter_direction(const Interaction& ref, const DirectionSample& ds) const {
    if (!ds.emitter || emitters_.empty()) return 0.f;
    return ds.emitter->pdf_direction(ref, ds) / float(emitters_.size());
}

std::pair<const Emitter*, float> Scene::sample_emitter_for_emission(float u) const {
    if (emission_distr_.empty()) return {nullptr, 0.f};
    const size_t index = emission_distr_.sample(u);
    return {emitters_[index].get(), emission_distr_.pmf(index)};
}

std::pair<size_t, float> Scene::sample_emitter_index_for_emission(float u) const {
    if (emission_distr_.empty()) return {0, 0.f};
    const size_t index = emission_distr_.sample(u);
    return {index, emission_distr_.pmf(index)};
}

float Scene::emission_probability(const Emitter* emitter) const {
    if (emission_distr_.empty()) return 0.f;
    for (size_t i = 0; i < emitters_.size(); ++i)
        if (emitters_[i].get() == emitter) return emission_distr_.pmf(i);
    return 0.f;
}

}  // namespace volguide
