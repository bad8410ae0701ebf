// volguide command line: render | train | merge | diff | convert | info | upgrade (docs/interface.md).
// Exit codes: 0 success, 1 input or I/O error (one line `volguide: FILE:LINE: message` on stderr),
// 2 usage error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "commands.h"
#include "volguide/core/error.h"

namespace {

using namespace volguide::cli;

// One line, whatever the message contains.
std::string one_line(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

void print_error(const std::string& where, const std::string& message) {
    if (where.empty())
        std::fprintf(stderr, "volguide: %s\n", one_line(message).c_str());
    else
        std::fprintf(stderr, "volguide: %s: %s\n", one_line(where).c_str(), one_line(message).c_str());
}

// The `render` subcommand and its options, parsed into `render`.
CLI::App* add_render_command(CLI::App& app, RenderArgs& render) {
    CLI::App* render_cmd = app.add_subcommand("render", "render a scene to an image");
    render_cmd->add_option("scene", render.scene, "Mitsuba 3 XML scene")->required();
    render_cmd
        ->add_option("-o,--output", render.outputs,
                     "output image (.exr: linear float32 RGB; .png: 8-bit sRGB); repeat for several formats")
        ->allow_extra_args(false);
    render_cmd->add_option("-D,--define", render.defines, "set a scene <default> (name=value); repeatable")
        ->allow_extra_args(false);
    render_cmd->add_option("--spp", render.spp, "samples per pixel (overrides the sampler's sample_count)");
    render_cmd->add_option("--time", render.time, "wall-clock budget in seconds (training included)");
    render_cmd->add_option("--seed", render.seed, "random seed (same seed, same image, any --threads)");
    render_cmd->add_option("--threads", render.threads, "worker threads (default: all)");
    render_cmd->add_option("--stats", render.stats, "write render statistics as JSON");
    render_cmd->add_option("--reference", render.reference,
                           "compare with this EXR: relMSE printed, convergence curve in --stats");
    render_cmd->add_flag("-q,--quiet", render.quiet, "no progress output");
    render_cmd->add_flag("--variance", render.variance,
                         "also write the per-sample variance of every pixel to <output>_var.exr (any integrator)");
    render_cmd->add_option("--field", render.field,
                           "render with this training file of `volguide train` (guided_volpath); trains nothing");
    render_cmd->add_option("--samples", render.samples,
                           "FIRST:COUNT: render sample indices [FIRST, FIRST+COUNT) of every pixel, a chunk for "
                           "`volguide merge` (excludes --spp)");
    render_cmd->add_option("--checkpoint", render.checkpoint,
                           "write the render's state to this file (atomically) at pass ends and when it stops, "
                           "for --resume");
    render_cmd->add_option("--checkpoint-every", render.checkpoint_every,
                           "seconds between checkpoints (default 60; one is always written when the render stops)");
    render_cmd->add_option("--resume", render.resume,
                           "go on from this checkpoint of the same scene, options and build to the target spp "
                           "(bit for bit the uninterrupted render)");
    return render_cmd;
}

// The `train` subcommand and its options, parsed into `train`.
CLI::App* add_train_command(CLI::App& app, TrainArgs& train) {
    CLI::App* train_cmd = app.add_subcommand(
        "train", "run the integrator's pre-pass once (guided_volpath: field, pixel estimate) and save it");
    train_cmd->add_option("scene", train.scene, "Mitsuba 3 XML scene")->required();
    train_cmd->add_option("-o,--output", train.output, "training file to write (for render --field)")->required();
    train_cmd->add_option("-D,--define", train.defines, "set a scene <default> (name=value); repeatable")
        ->allow_extra_args(false);
    train_cmd->add_option("--time", train.time,
                          "the render job's budget in seconds, as in render --time (training gets its share)");
    train_cmd->add_option("--seed", train.seed, "random seed of the training");
    train_cmd->add_option("--spp", train.spp,
                          "the frame's samples per pixel, as in render --spp");
    train_cmd->add_option("--threads", train.threads, "worker threads (default: all)");
    train_cmd->add_flag("-q,--quiet", train.quiet, "no progress output");
    return train_cmd;
}

// The `merge` subcommand and its options, parsed into `merge`.
CLI::App* add_merge_command(CLI::App& app, MergeArgs& merge) {
    CLI::App* merge_cmd = app.add_subcommand(
        "merge", "combine the parts of one render (--samples chunks) into the image of all their samples");
    merge_cmd->add_option("parts", merge.parts, "part images (.exr written by volguide render or merge)")
        ->required();
    merge_cmd->add_option("-o,--output", merge.output, "merged image (.exr; variance to <output>_var.exr)")
        ->required();
    return merge_cmd;
}

// The `diff` subcommand and its options, parsed into `diff`.
CLI::App* add_diff_command(CLI::App& app, DiffArgs& diff) {
    CLI::App* diff_cmd = app.add_subcommand("diff", "compare an image with a reference");
    diff_cmd->add_option("image", diff.image, "image (.exr)")->required();
    diff_cmd->add_option("reference", diff.reference, "reference image (.exr)")->required();
    diff_cmd->add_flag("--json", diff.json, "print the metrics as one JSON object");
    diff_cmd->add_option("--error-image", diff.error_image,
                         "write the per-pixel relative squared error (EXR: raw values; PNG: false colour)");

    diff_cmd->add_option("--min-reference", diff.min_reference,
                         "compare only the pixels whose reference (mean of channels) exceeds this value");
    return diff_cmd;
}

// The `convert` subcommand and its options, parsed into `convert`.
CLI::App* add_convert_command(CLI::App& app, ConvertArgs& convert) {
    CLI::App* convert_cmd = app.add_subcommand("convert", "convert an image (EXR <-> PNG), optionally rescaled");
    convert_cmd->add_option("input", convert.input, "input image (.exr, .png)")->required();
    convert_cmd->add_option("output", convert.output, "output image (.exr, .png)")->required();
    convert_cmd->add_option("--exposure", convert.exposure, "scale by 2^EXPOSURE (stops)");
    return convert_cmd;
}

// The `upgrade` subcommand and its options, parsed into `upgrade`.
CLI::App* add_upgrade_command(CLI::App& app, UpgradeArgs& upgrade) {
    CLI::App* cmd = app.add_subcommand("upgrade", "write a Mitsuba 0.x (0.4-0.6) scene in Mitsuba 3's form");
    cmd->add_option("scene", upgrade.scene, "Mitsuba 0.x XML scene")->required();
    cmd->add_option("-o,--output", upgrade.output, "the upgraded scene (.xml)")->required();
    cmd->add_option("-D,--define", upgrade.defines, "set a scene <default> (name=value); repeatable")
        ->allow_extra_args(false);
    return cmd;
}

// The `info` subcommand and its options, parsed into `info`.
CLI::App* add_info_command(CLI::App& app, InfoArgs& info) {
    CLI::App* info_cmd = app.add_subcommand("info", "summarise a scene, or a saved guiding field (--field)");
    info_cmd->add_option("scene", info.scene, "Mitsuba 3 XML scene");
    info_cmd->add_option("--field", info.field,
                         "a guiding field written by guided_volpath's save_field, or a training file of `volguide train`");
    info_cmd->add_option("-D,--define", info.defines, "set a scene <default> (name=value); repeatable")
        ->allow_extra_args(false);
    return info_cmd;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace volguide::cli;
    CLI::App app{"volguide: a physically based renderer for Mitsuba 3 scenes with volume path guiding",
                 "volguide"};
    app.require_subcommand(1);
    // --version: what optional peers are built in (Open PGL: the openpgl_volpath integrator).
#if VOLGUIDE_HAVE_OPENPGL
    app.set_version_flag("--version", "volguide\nIntel Open PGL " VOLGUIDE_OPENPGL_VERSION
                                      ": built in (integrator openpgl_volpath)");
#else
    app.set_version_flag("--version", "volguide\nIntel Open PGL: not built in (integrator openpgl_volpath unavailable)");
#endif

    RenderArgs render;
    TrainArgs train;
    MergeArgs merge;
    DiffArgs diff;
    ConvertArgs convert;
    InfoArgs info;
    UpgradeArgs upgrade;
    CLI::App* render_cmd = add_render_command(app, render);
    CLI::App* train_cmd = add_train_command(app, train);
    CLI::App* merge_cmd = add_merge_command(app, merge);
    CLI::App* diff_cmd = add_diff_command(app, diff);
    CLI::App* convert_cmd = add_convert_command(app, convert);
    add_info_command(app, info);
    CLI::App* upgrade_cmd = add_upgrade_command(app, upgrade);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);  // prints the message and a hint
        return 2;
    }

    std::string context;  // the file an error without location refers to
    try {
        if (render_cmd->parsed()) {
            context = render.scene;
            return run_render(render);
        }
        if (train_cmd->parsed()) {
            context = train.scene;
            return run_train(train);
        }
        if (merge_cmd->parsed()) {
            context = merge.output;
            return run_merge(merge);
        }
        if (diff_cmd->parsed()) {
            context = diff.image;
            return run_diff(diff);
        }
        if (convert_cmd->parsed()) {
            context = convert.input;
            return run_convert(convert);
        }
        if (upgrade_cmd->parsed()) {
            context = upgrade.scene;
            return run_upgrade(upgrade);
        }
        context = info.field.empty() ? info.scene : info.field;
        return run_info(info);
    } catch (const UsageError& e) {
        print_error("", e.what());
        std::fprintf(stderr, "Run with --help for more information.\n");
        return 2;
    } catch (const volguide::InputError& e) {
        print_error(e.location().file.empty() ? context : e.location().str(), e.message());
        return 1;
    } catch (const FileError& e) {
        print_error(e.file, e.what());
        return 1;
    } catch (const std::exception& e) {
        print_error(context, e.what());
        return 1;
    }
}
