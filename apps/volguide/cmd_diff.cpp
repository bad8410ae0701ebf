// `volguide diff`: relMSE (eps 1e-2 and 1e-3, plain and without the top 0.01 % pixels), MSE, means
// and their ratio.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"

namespace volguide::cli {

int run_diff(const DiffArgs& args) {
    if (!args.error_image.empty()) {
        std::string ext = extension_of(args.error_image);
        if (ext != ".exr" && ext != ".png")
            throw UsageError(fmt::format("--error-image '{}' must end in .exr or .png", args.error_image));
    }
    Image image = read_image(args.image), reference = read_image(args.reference);
    if (image.width != reference.width || image.height != reference.height)
        throw FileError(args.image,
                        fmt::format("size {}x{} differs from the reference '{}' ({}x{})", image.width,
                                    image.height, args.reference, reference.width, reference.height));
    ImageDiff d = args.min_reference ? compare_images(image, reference, *args.min_reference)
                                     : compare_images(image, reference);
    // EXR: the raw per-channel relative squared errors; PNG: a false-colour map for viewing.
    if (!args.error_image.empty())
        write_image(args.error_image, extension_of(args.error_image) == ".png"
                                          ? relative_error_heatmap(image, reference, 1e-2)
                                          : relative_error_image(image, reference, 1e-2));
    if (args.json) {
        nlohmann::json j{{"relmse_1e-2", d.relmse_1e2},
                         {"relmse_1e-3", d.relmse_1e3},
                         {"relmse_1e-2_trimmed", d.relmse_1e2_trimmed},
                         {"relmse_1e-3_trimmed", d.relmse_1e3_trimmed},
                         {"mse", d.mse},
                         {"mean", d.mean},
                         {"reference_mean", d.reference_mean}};
        j["ratio"] = std::isfinite(d.ratio) ? nlohmann::json(d.ratio) : nlohmann::json(nullptr);
        j["nonfinite"] = d.nonfinite;
        j["pixels"] = d.pixels;
        fmt::print("{}\n", j.dump());
        return 0;
    }
    fmt::print("relMSE(1e-2): {:.6g}\n", d.relmse_1e2);
    fmt::print("relMSE(1e-3): {:.6g}\n", d.relmse_1e3);
    fmt::print("relMSE(1e-2) without the top 0.01% pixels: {:.6g}\n", d.relmse_1e2_trimmed);
    fmt::print("relMSE(1e-3) without the top 0.01% pixels: {:.6g}\n", d.relmse_1e3_trimmed);
    fmt::print("MSE: {:.6g}\n", d.mse);
    fmt::print("mean: {:.6g}\n", d.mean);
    fmt::print("reference mean: {:.6g}\n", d.reference_mean);
    fmt::print("ratio: {:.6g}\n", d.ratio);
    if (d.nonfinite > 0) fmt::print("non-finite values (excluded): {}\n", d.nonfinite);
    if (args.min_reference)
        fmt::print("pixels compared: {} of {} (reference mean > {})\n", d.pixels, image.pixels.size(),
                   *args.min_reference);
    return 0;
}

}  // namespace volguide::cli
