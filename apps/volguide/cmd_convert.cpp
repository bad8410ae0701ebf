// `volguide convert`: an image in another format (EXR <-> PNG), optionally scaled by 2^exposure, e.g.
// PNG previews of EXR renders for the benchmark report.
#include <fmt/format.h>

#include <cmath>

#include "cli_util.h"
#include "commands.h"
#include "volguide/render/image_io.h"

namespace volguide::cli {

int run_convert(const ConvertArgs& args) {
    std::string ext = extension_of(args.output);
    if (ext != ".exr" && ext != ".png")
        throw UsageError(fmt::format("output '{}' must end in .exr or .png", args.output));
    if (!std::isfinite(args.exposure))
        throw UsageError(fmt::format("--exposure must be a finite number of stops, got {}", args.exposure));
    Image image = read_image(args.input);
    const float scale = float(std::exp2(args.exposure));
    if (scale != 1.f)
        for (Color3& c : image.pixels) c = c * scale;
    write_image(args.output, image);
    return 0;
}

}  // namespace volguide::cli
