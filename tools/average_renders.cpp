// average_renders OUT.exr IN1.exr IN2.exr [...]: the mean of k >= 2 independent renders (different
// seeds) of one image, written to OUT.exr, and the estimated relMSE/MSE of that mean from the spread
// of the renders, printed as one JSON object. The benchmark references are made with it
// (bench/make_references.py), so each reference carries its own error estimate.
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"

int main(int argc, char** argv) {
    using namespace volguide;
    if (argc < 4) {
        std::fprintf(stderr, "usage: average_renders OUT.exr IN1.exr IN2.exr [IN3.exr ...]\n");
        return 2;
    }
    try {
        std::vector<Image> renders;
        std::vector<std::string> inputs;
        for (int k = 2; k < argc; ++k) {
            inputs.push_back(argv[k]);
            renders.push_back(read_image(argv[k]));
            if (renders.back().width != renders.front().width || renders.back().height != renders.front().height)
                throw std::runtime_error(fmt::format("{}: size differs from {}", argv[k], argv[2]));
        }
        MeanEstimate m = mean_of_renders(renders);
        write_exr(argv[1], m.mean);
        nlohmann::json j{{"output", argv[1]},       {"inputs", inputs},           {"renders", renders.size()},
                         {"relmse_1e-2", m.relmse_1e2}, {"relmse_1e-3", m.relmse_1e3}, {"mse", m.mse}};
        fmt::print("{}\n", j.dump());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "average_renders: %s\n", e.what());
    }
    return 1;
}
