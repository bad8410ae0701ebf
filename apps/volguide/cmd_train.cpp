// `volguide train`: the integrator's pre-pass alone (guided_volpath: the guiding field and the
// pixel estimate), written as a training file for `volguide render --field` (docs/distributed.md).
#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "cli_util.h"
#include "commands.h"
#include "interrupt.h"
#include "progress_display.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/integrators/guided/prepass/training_file.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"
#include "volguide/scene/scene_fingerprint.h"

namespace volguide::cli {

namespace {

void validate(const TrainArgs& a) {
    if (a.output.empty()) throw UsageError("train needs -o FIELD (the training file to write)");
    if (a.time && !(*a.time > 0 && std::isfinite(*a.time)))
        throw UsageError(fmt::format("--time must be a positive number of seconds, got {}", *a.time));
    if (a.threads && *a.threads <= 0) throw UsageError(fmt::format("--threads must be positive, got {}", *a.threads));
    const std::filesystem::path dir = std::filesystem::path(a.output).parent_path();
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
        throw FileError(a.output, fmt::format("directory '{}' does not exist", dir.string()));
}

}  // namespace

int run_train(const TrainArgs& args) {
    validate(args);
    LoadOptions load;
    load.defines = parse_defines(args.defines);
    std::unique_ptr<Scene> scene = load_scene(args.scene, load);
    Integrator& integrator = const_cast<Integrator&>(scene->integrator());
    if (!integrator.has_prepass_state())
        throw FileError(args.scene, fmt::format("the integrator {} has no pre-pass to train (train needs guided_volpath)",
                                                integrator.configuration()));

    InterruptGuard interrupt;
    ProgressDisplay display(args.quiet);
    RenderOptions options;
    // --time is the budget of the render job the training belongs to, as in `render --time`:
    // guided_volpath trains for its training_fraction of it, so train + render --field gives the
    // field a single `render --time` would train.
    if (args.time) options.time_budget = *args.time;
    if (args.spp) {
        if (*args.spp <= 0) throw UsageError(fmt::format("--spp must be positive, got {}", *args.spp));
        options.spp = *args.spp;
    }
    options.seed = args.seed;
    if (args.threads) options.threads = *args.threads;
    options.cancel = interrupt.flag();
    options.progress = [&](const Progress& p) { display.update(p); };
    const double seconds = run_preprocess(*scene, integrator, options);
    display.finish();
    if (interrupt.interrupted())
        throw FileError(args.output, "interrupted during training; nothing was written");

    TrainingFile file;
    file.scene = scene_fingerprint(args.scene, load.defines);
    file.scene_file = args.scene;
    file.integrator = integrator.configuration();
    file.seed = args.seed.value_or(scene->sensor().seed());
    file.prepass = integrator.prepass_state();
    try {
        save_training(args.output, file);
    } catch (const TrainingFileError& e) {
        throw FileError(args.output, e.what());
    }
    fmt::print("time: {:.3f} s (training)\n", seconds);
    fmt::print("field fingerprint: {}\n", prepass_fingerprint(file.prepass));
    fmt::print("output: {}\n", args.output);
    return 0;
}

}  // namespace volguide::cli
