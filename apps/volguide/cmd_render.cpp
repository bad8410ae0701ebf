// `volguide render`: load, render (progressive, interruptible by Ctrl-C or SIGTERM), then write the image
// atomically; an EXR is a part of a distributed render (render_part.h): with `--field` the pre-pass
// comes from a training file, with `--samples FIRST:COUNT` only those sample indices are rendered.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "interrupt.h"
#include "progress_display.h"
#include "render_checkpoints.h"
#include "scene_identity.h"
#include "volguide/core/atomic_write.h"
#include "volguide/core/log.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"
#include "volguide/render/render_part.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"
#include "volguide/scene/scene_fingerprint.h"

namespace volguide::cli {

namespace {

void check_directory(const std::string& file);

void validate(const RenderArgs& a, const std::vector<std::string>& outputs) {
    if (a.spp && *a.spp <= 0) throw UsageError(fmt::format("--spp must be positive, got {}", *a.spp));
    if (a.time && !(*a.time > 0 && std::isfinite(*a.time)))
        throw UsageError(fmt::format("--time must be a positive number of seconds, got {}", *a.time));
    if (a.threads && *a.threads <= 0)
        throw UsageError(fmt::format("--threads must be positive, got {}", *a.threads));
    for (const std::string& output : outputs) {
        std::string ext = extension_of(output);
        if (ext != ".exr" && ext != ".png")
            throw UsageError(fmt::format("output '{}' must end in .exr or .png", output));
    }
    if (!a.stats.empty() && extension_of(a.stats) != ".json")
        throw UsageError(fmt::format("--stats file '{}' must end in .json", a.stats));
    if (!a.reference.empty() && extension_of(a.reference) != ".exr")
        throw UsageError(fmt::format("--reference '{}' must be an .exr image", a.reference));
    if (!a.samples.empty() && a.spp) throw UsageError("--samples FIRST:COUNT and --spp exclude each other");
    if (!(a.checkpoint_every > 0 && std::isfinite(a.checkpoint_every)))
        throw UsageError(fmt::format("--checkpoint-every must be a positive number of seconds, got {}", a.checkpoint_every));
    if (!a.checkpoint.empty()) check_directory(a.checkpoint);
}

// --samples FIRST:COUNT: one range with COUNT > 0.
std::optional<SampleRange> sample_range(const std::string& text) {
    if (text.empty()) return std::nullopt;
    SampleRanges ranges;
    try {
        ranges = parse_ranges(text);
    } catch (const std::invalid_argument& e) {
        throw UsageError(fmt::format("--samples: {}", e.what()));
    }
    if (ranges.size() != 1 || ranges[0].count == 0 || ranges[0].count > uint64_t(1) << 30)
        throw UsageError(fmt::format("--samples expects one FIRST:COUNT with 0 < COUNT <= 2^30, got '{}'", text));
    return ranges[0];
}

// The EXR of a render: a part of the render of its seed, field and integrator (render_part.h).
RenderPart make_part(const RenderResult& r, const Integrator& integrator, const std::string& scene_file,
                     const std::string& scene_fingerprint) {
    RenderPart part;
    part.mean = r.mean;
    part.variance = r.variance;
    part.weight = r.weight;
    part.info.scene = scene_fingerprint;
    part.info.scene_file = scene_file;
    part.info.seed = r.stats.seed;
    part.info.field = field_fingerprint(integrator);
    part.info.integrator = integrator.configuration();
    part.info.samples = normalized({SampleRange{r.first_sample, uint64_t(r.spp)}});
    return part;
}

// One point of the convergence curve against --reference.
struct ConvergencePoint {
    int spp = 0;
    double seconds = 0;
    ImageDiff diff;
};

nlohmann::json diff_json(const ImageDiff& d) {
    return {{"relmse_1e-2", d.relmse_1e2},
            {"relmse_1e-3", d.relmse_1e3},
            {"relmse_1e-2_trimmed", d.relmse_1e2_trimmed},
            {"relmse_1e-3_trimmed", d.relmse_1e3_trimmed},
            {"mse", d.mse},
            {"mean", d.mean},
            {"reference_mean", d.reference_mean}};
}

// Fail before a long render, not after it, when an output cannot be written.
void check_directory(const std::string& file) {
    std::filesystem::path dir = std::filesystem::path(file).parent_path();
    if (dir.empty()) return;
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw FileError(file, fmt::format("directory '{}' does not exist", dir.string()));
}

void write_stats(const std::string& path, const RenderArgs& args, const std::vector<std::string>& outputs,
                 const std::string& variance_output, double load_seconds, const RenderResult& r,
                 const std::optional<ImageDiff>& final_diff, const std::vector<ConvergencePoint>& convergence,
                 const Integrator& integrator) {
    const RenderStats& s = r.stats;
    nlohmann::json j;
    j["scene"] = args.scene;
    j["output"] = outputs.front();
    j["outputs"] = outputs;
    if (!variance_output.empty()) j["variance_output"] = variance_output;
    j["width"] = r.mean.width;
    j["height"] = r.mean.height;
    j["spp"] = r.spp;
    j["sample_range"] = {{"first", r.first_sample}, {"count", r.spp}};
    if (!args.field.empty()) j["field"] = args.field;
    j["spp_requested"] = args.spp ? *args.spp : 0;
    j["time_budget"] = args.time ? *args.time : 0.0;
    j["seed"] = s.seed;
    j["threads"] = s.threads;
    j["passes"] = s.passes;
    j["samples"] = s.samples;
    j["discarded_samples"] = s.discarded_samples;
    j["nonfinite_samples"] = s.nonfinite_samples;
    if (s.first_nonfinite)
        j["first_nonfinite"] = {
            {"x", s.first_nonfinite->x}, {"y", s.first_nonfinite->y}, {"sample", s.first_nonfinite->sample}};
    j["cancelled"] = s.cancelled;
    j["time_limited"] = s.time_limited;
    j["time"] = {{"load", load_seconds},
                 {"preprocess", s.preprocess_seconds},
                 {"render", s.render_seconds},
                 {"render_cpu", s.render_cpu_seconds},
                 {"total", s.total_seconds},
                 {"total_with_load", load_seconds + s.total_seconds}};
    if (final_diff) {
        j["reference"] = diff_json(*final_diff);
        j["reference"]["file"] = args.reference;
        nlohmann::json curve = nlohmann::json::array();
        for (const ConvergencePoint& p : convergence) {
            nlohmann::json point = diff_json(p.diff);
            point["spp"] = p.spp;
            point["seconds"] = p.seconds;
            curve.push_back(point);
        }
        j["convergence"] = curve;
    }
    nlohmann::json counters = nlohmann::json::object();
    for (const auto& [name, value] : integrator.statistics()) counters[name] = value;
    j["integrator"] = counters;
    // Atomic and checked after close like the images: a full disk must not leave half a JSON file.
    const std::string text = j.dump(2) + "\n";
    const std::string error = write_atomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp);
        f << text;
        f.close();
        if (!f) throw std::runtime_error("write failed");
    });
    if (!error.empty()) throw FileError(path, "cannot write the statistics file: " + error);
}

}  // namespace

int run_render(const RenderArgs& args) {
    const std::vector<std::string> outputs =
        args.outputs.empty() ? std::vector<std::string>{default_output(args.scene)} : args.outputs;
    validate(args, outputs);
    const std::optional<SampleRange> samples = sample_range(args.samples);
    for (const std::string& output : outputs) check_directory(output);
    if (!args.stats.empty()) check_directory(args.stats);
    LoadOptions load;
    load.defines = parse_defines(args.defines);
    std::vector<std::string> xml_files;
    load.xml_files = &xml_files;

    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Scene> scene = load_scene(args.scene, load);
    const std::string scene_id = scene_fingerprint(args.scene, load.defines);
    // The scene owns its integrator; a given pre-pass replaces its training.
    Integrator& integrator = const_cast<Integrator&>(scene->integrator());
    if (!args.field.empty()) use_training_file(args.field, scene_id, integrator);
    const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::optional<Image> reference;
    if (!args.reference.empty()) {
        reference = read_image(args.reference);
        const Film& film = scene->sensor().film();
        if (reference->width != film.width() || reference->height != film.height())
            throw FileError(args.reference, fmt::format("size {}x{} differs from the film's {}x{}",
                                                        reference->width, reference->height, film.width(),
                                                        film.height()));
    }

    InterruptGuard interrupt;
    ProgressDisplay display(args.quiet);
    RenderOptions options;
    if (args.spp) options.spp = *args.spp;
    if (samples) {
        options.first_sample = samples->first;
        options.spp = int(samples->count);
    }
    if (args.time) options.time_budget = *args.time;
    options.seed = args.seed;
    if (args.threads) options.threads = *args.threads;
    options.variance = args.variance;
    options.cancel = interrupt.flag();
    options.progress = [&](const Progress& p) { display.update(p); };
    // Convergence against the reference at 1, 2, 4, ... spp (and the final image below).
    std::vector<ConvergencePoint> convergence;
    if (reference)
        options.on_pass = [&](int spp, double seconds, const Image& mean) {
            if ((spp & (spp - 1)) == 0) convergence.push_back({spp, seconds, compare_images(mean, *reference)});
        };
    RenderCheckpoints checkpoints(args, *scene, scene_id, xml_files, options);
    checkpoints.attach(options);
    RenderResult result = render(*scene, options);
    display.finish();
    std::optional<ImageDiff> final_diff;
    if (reference && result.spp > 0) {
        final_diff = compare_images(result.mean, *reference);
        if (convergence.empty() || convergence.back().spp != result.spp)
            convergence.push_back({result.spp, result.stats.total_seconds, *final_diff});
    }

    if (result.spp == 0)
        throw FileError(outputs.front(), "interrupted before the first pass completed; nothing was written");
    const RenderPart part = make_part(result, integrator, args.scene, scene_id);
    for (const std::string& output : outputs)
        if (extension_of(output) == ".exr")
            write_part(output, part);
        else
            write_image(output, result.mean, scene->sensor().film().png_tonemap());  // an ldrfilm's tonemap
    std::string var_output;
    if (scene->integrator().writes_variance() || args.variance) {
        var_output = variance_path(outputs.front());
        write_exr(var_output, result.variance);
    }
    if (!args.stats.empty()) write_stats(args.stats, args, outputs, var_output, load_seconds, result, final_diff,
                                          convergence, scene->integrator());

    const RenderStats& s = result.stats;
    if (s.cancelled) fmt::print("interrupted: wrote the {} completed samples per pixel\n", result.spp);
    fmt::print("time: {:.3f} s (load {:.3f} s, preprocess {:.3f} s, render {:.3f} s)\n",
               load_seconds + s.total_seconds, load_seconds, s.preprocess_seconds, s.render_seconds);
    fmt::print("spp: {}\n", result.spp);
    fmt::print("samples: {}:{}\n", result.first_sample, result.spp);
    if (s.nonfinite_samples > 0) {
        fmt::print("non-finite samples dropped: {}\n", s.nonfinite_samples);
        const SampleLocation& at = *s.first_nonfinite;
        warn({}, "{} non-finite samples were dropped; the first: pixel ({}, {}) sample {} (seed {})",
             s.nonfinite_samples, at.x, at.y, at.sample, s.seed);
    }
    if (final_diff)
        fmt::print("relMSE vs reference: {:.6g} (eps 1e-2), {:.6g} (eps 1e-3); MSE {:.6g}\n",
                   final_diff->relmse_1e2, final_diff->relmse_1e3, final_diff->mse);
    for (const std::string& output : outputs) fmt::print("output: {}\n", output);
    if (const std::string c = checkpoints.summary(); !c.empty()) fmt::print("{}\n", c);
    if (!var_output.empty()) fmt::print("variance: {}\n", var_output);
    return 0;
}

}  // namespace volguide::cli
