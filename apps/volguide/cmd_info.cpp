// `volguide info`: what a scene contains, as volguide loaded it.
#include <fmt/format.h>

#include "cli_util.h"
#include "commands.h"
#include <fstream>

#include "volguide/core/memory.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"
#include "volguide/integrators/guided/prepass/training_file.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

namespace volguide::cli {

namespace {

bool is_training_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[8] = {};
    in.read(magic, 8);
    return in.gcount() == 8 && std::string(magic, 7) == "VGTRAIN";
}

// A guiding field file (save_field), or a training file of `volguide train` (its metadata first).
GuidingField read_field_or_training(const std::string& path) {
    try {
        if (!is_training_file(path)) return load_field(path);
        const TrainingFile training = load_training(path);
        fmt::print("training file: {}\n", path);
        fmt::print("trained for: {} (scene fingerprint {}, seed {})\n", training.scene_file, training.scene,
                   training.seed);
        fmt::print("integrator: {}\n", training.integrator);
        fmt::print("field fingerprint: {}\n", prepass_fingerprint(training.prepass));
        const GuidedPrepass prepass = deserialize_guided_prepass(training.prepass);
        if (!prepass.pixel_estimate.pixels.empty())
            fmt::print("pixel estimate: {} x {}\n", prepass.pixel_estimate.width, prepass.pixel_estimate.height);
        return prepass.field;
    } catch (const FieldFormatError& e) {
        throw FileError(path, e.what());
    } catch (const TrainingFileError& e) {
        throw FileError(path, e.what());
    }
}

int run_field_info(const std::string& path) {
    const GuidingField field = read_field_or_training(path);
    size_t valid = 0, samples = 0, lobes = 0, max_samples = 0;
    for (const GuidingLeaf& leaf : field.leaves()) {
        samples += leaf.samples;
        max_samples = std::max<size_t>(max_samples, leaf.samples);
        if (!leaf.valid) continue;
        ++valid;
        lobes += size_t(leaf.vmm.size());
    }
    const size_t leaves = field.leaves().size();
    const size_t bytes = leaves * sizeof(GuidingLeaf) + field.tree().nodes().size() * sizeof(SpatialTree::Node) +
                         leaves * sizeof(BBox3f);
    const BBox3f& b = field.tree().bounds();
    fmt::print("field: {}\n", path);
    fmt::print("bounds: [{}, {}, {}] - [{}, {}, {}]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    fmt::print("leaves: {} ({} valid, {} invalid), tree depth {}\n", leaves, valid, leaves - valid, field.tree().depth());
    fmt::print("samples: {} (max {} per leaf)\n", samples, max_samples);
    fmt::print("lobes per valid leaf: {:.2f}\n", valid ? double(lobes) / double(valid) : 0.0);
    fmt::print("memory: {:.2f} MiB ({} bytes per leaf)\n", double(bytes) / (1024.0 * 1024.0), leaves ? bytes / leaves : 0);
    return 0;
}

}  // namespace

int run_info(const InfoArgs& args) {
    if (args.field.empty() == args.scene.empty())
        throw UsageError("info takes either a scene or --field FILE");
    if (!args.field.empty()) return run_field_info(args.field);
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
    // The film's share of a render's memory (accumulators, result images, EXR channels); meshes,
    // grids and the guiding field come on top.
    fmt::print("film memory: {} (the limit is {})\n", format_bytes(film_memory_bytes(film.width(), film.height())),
               memory_budget_description());
    fmt::print("sensor: {}\n", sensor.to_string());
    fmt::print("filter: {}{}\n", film.filter().to_string(), film.sample_border() ? " (sample_border)" : "");
    fmt::print("integrator: {}\n", scene->integrator().to_string());
    fmt::print("shapes: {} ({} triangle meshes, {} triangles)\n", scene->shapes().size(), meshes, triangles);
    fmt::print("emitters: {} ({} area{})\n", scene->emitters().size(), area,
               scene->environment() ? ", with an environment" : "");
    fmt::print("bbox: [{}, {}, {}] - [{}, {}, {}]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    if (scene->integrator().writes_variance()) fmt::print("variance: written to <output stem>_var.exr\n");
#if VOLGUIDE_HAVE_OPENPGL
    fmt::print("openpgl: built in (Intel Open PGL {}; integrator openpgl_volpath)\n", VOLGUIDE_OPENPGL_VERSION);
#else
    fmt::print("openpgl: not built in (integrator openpgl_volpath unavailable)\n");
#endif
    return 0;
}

}  // namespace volguide::cli
