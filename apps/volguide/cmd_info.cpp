// `volguide info`: what a scene contains, as volguide loaded it.
#include <fmt/format.h>

#include "cli_util.h"
#include "commands.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

namespace volguide::cli {

int run_info(const InfoArgs& args) {
    LoadOptions load;
    load.defines = parse_defines(args.defines);
    std::unique_ptr<Scene> scene = load_scene(args.scene, load);
    const Sensor& sensor = scene->sensor();
    const Film& film = sensor.film();
    size_t triangles = 0, meshes = 0;
    for (const auto& shape : scene->shapes())
        if (const TriangleMesh* mesh = shape->triangle_mesh()) {
            triangles += mesh->triangle_count();
            ++meshes;
        }
    size_t area = 0;
    for (const auto& e : scene->emitters())
        if ((e->flags() & emitter_flags::Surface) != 0) ++area;
    const BBox3f& b = scene->bbox();
    fmt::print("scene: {}\n", args.scene);
    fmt::print("resolution: {} x {}\n", film.width(), film.height());
    fmt::print("spp: {} (seed {})\n", sensor.sample_count(), sensor.seed());
    fmt::print("sensor: {}\n", sensor.to_string());
    fmt::print("filter: {}{}\n", film.filter().to_string(), film.sample_border() ? " (sample_border)" : "");
    fmt::print("integrator: {}\n", scene->integrator().to_string());
    fmt::print("shapes: {} ({} triangle meshes, {} triangles)\n", scene->shapes().size(), meshes, triangles);
    fmt::print("emitters: {} ({} area{})\n", scene->emitters().size(), area,
               scene->environment() ? ", with an environment" : "");
    fmt::print("bbox: [{}, {}, {}] - [{}, {}, {}]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    if (scene->integrator().writes_variance()) fmt::print("variance: written to <output stem>_var.exr\n");
    return 0;
}

}  // namespace volguide::cli
