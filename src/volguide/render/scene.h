#pragma once
// The render-ready scene: shapes behind an acceleration structure, emitters, one sensor and the
// integrator to run.
#include <memory>
#include <utility>
#include <vector>

#include "volguide/core/bbox.h"
#include "volguide/core/distribution.h"
#include "volguide/core/properties.h"
#include "volguide/geometry/accel.h"
#include "volguide/geometry/shape.h"
#include "volguide/render/emitter.h"
#include "volguide/render/sensor.h"

namespace volguide {

class BSDF;
class Integrator;

class Scene {
public:
    // Takes the root <scene> record's shapes, emitters and sensor, the integrator to run and the BSDF
    // of every shape without one (the loader, scene/loader.h's make_scene, chooses both).
    Scene(const Properties& root, std::shared_ptr<Integrator> integrator, const std::shared_ptr<BSDF>& default_bsdf);
    ~Scene();

    bool intersect(const Ray& ray, SurfaceInteraction& si) const { return accel_->intersect(ray, si); }
    bool occluded(const Ray& ray) const { return accel_->occluded(ray); }

    // Chooses an emitter uniformly (as Mitsuba 3) and samples a direction on it. The weight
    // includes 1/(choice probability); with test_visibility it is zero when occluded.
    std::pair<DirectionSample, Color3> sample_emitter_direction(const Interaction& ref, Point2f u,
                                                                bool test_visibility) const;
    // Solid-angle pdf of sample_emitter_direction producing ds (including the choice probability).
    float pdf_emitter_direction(const Interaction& ref, const DirectionSample& ds) const;

    // Emitter choice for photon emission, proportional to power() (channel average), with its
    // probability; {nullptr, 0} when no emitter has power. Built once when the scene is assembled.
    std::pair<const Emitter*, float> sample_emitter_for_emission(float u) const;
    // The same choice as an index into emitters() (for per-emitter tables); probability 0 when none.
    std::pair<size_t, float> sample_emitter_index_for_emission(float u) const;
    // Probability that sample_emitter_for_emission picks `emitter`.
    float emission_probability(const Emitter* emitter) const;

    const std::vector<std::shared_ptr<Shape>>& shapes() const { return shapes_; }
    const std::vector<std::shared_ptr<Emitter>>& emitters() const { return emitters_; }
    // The environment emitter evaluated by rays that leave the scene (nullptr when none).
    const Emitter* environment() const { return environment_; }
    // The emitter a ray sees at `si` (the environment when it missed); nullptr when none.
    const Emitter* emitter_seen(const SurfaceInteraction& si) const {
        return si.is_valid() ? si.shape->emitter() : environment_;
    }
    const Sensor& sensor() const { return *sensor_; }
    const Integrator& integrator() const { return *integrator_; }
    const BBox3f& bbox() const { return bbox_; }

private:
    std::vector<std::shared_ptr<Shape>> shapes_;
    std::vector<std::shared_ptr<Emitter>> emitters_;  // all emitters, area ones included
    const Emitter* environment_ = nullptr;
    std::shared_ptr<Sensor> sensor_;
    std::shared_ptr<Integrator> integrator_;
    std::unique_ptr<Accel> accel_;
    BBox3f bbox_;
    DiscreteDistribution emission_distr_;  // over emitters_, by power; empty when none emits
};

// The bounds a guiding structure covers (guided_volpath's field, Open PGL's): the scene's shapes
// (media are bounded by shapes or grids) with a small margin.
BBox3f guiding_bounds(const Scene& scene);

}  // namespace volguide
