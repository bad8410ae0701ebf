// average_renders OUT.exr [--earlier MEAN.exr N] IN1.exr IN2.exr [...]: the mean of k >= 2 independent
// renders (different seeds) of one image, written to OUT.exr, and the estimated relMSE/MSE of that mean
// from the spread of the renders, printed as one JSON object. The benchmark references are made with it
// (bench/make_references.py), so each reference carries its own error estimate. With --earlier, MEAN.exr
// is the mean of N renders made before of the same kind (a reference being made longer): OUT.exr is the
// mean of all N + k, its error estimated from the spread of the k new ones (image_compare.h).
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"

namespace {

constexpr const char* kUsage = "usage: average_renders OUT.exr [--earlier MEAN.exr N] IN1.exr IN2.exr [IN3.exr ...]\n";

int parse_count(const std::string& s) {
    size_t used = 0;
    int n = 0;
    try {
        n = std::stoi(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != s.size() || n < 1)
        throw std::runtime_error(fmt::format("--earlier: '{}' is not a number of renders (>= 1)", s));
    return n;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace volguide;
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (args.size() < 3) {
            std::fprintf(stderr, "%s", kUsage);
            return 2;
        }
        const std::string out = args[0];
        std::optional<std::string> earlier_path;
        int earlier_count = 0;
        size_t first = 1;
        if (args[1] == "--earlier") {
            if (args.size() < 6) {
                std::fprintf(stderr, "%s", kUsage);
                return 2;
            }
            earlier_path = args[2];
            earlier_count = parse_count(args[3]);
            first = 4;
        }
        std::vector<Image> renders;
        std::vector<std::string> inputs(args.begin() + long(first), args.end());
        for (const std::string& in : inputs) {
            renders.push_back(read_image(in));
            if (renders.back().width != renders.front().width || renders.back().height != renders.front().height)
                throw std::runtime_error(fmt::format("{}: size differs from {}", in, inputs.front()));
        }
        MeanEstimate m;
        if (earlier_path) {
            const Image earlier = read_image(*earlier_path);
            if (earlier.width != renders.front().width || earlier.height != renders.front().height)
                throw std::runtime_error(fmt::format("{}: size differs from {}", *earlier_path, inputs.front()));
            m = mean_with_earlier(earlier, earlier_count, renders);
        } else {
            m = mean_of_renders(renders);
        }
        write_exr(out, m.mean);
        nlohmann::json j{{"output", out},       {"inputs", inputs},           {"renders", renders.size() + size_t(earlier_count)},
                         {"relmse_1e-2", m.relmse_1e2}, {"relmse_1e-3", m.relmse_1e3}, {"mse", m.mse}};
        if (earlier_path) j["earlier"] = {{"mean", *earlier_path}, {"renders", earlier_count}};
        fmt::print("{}\n", j.dump());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "average_renders: %s\n", e.what());
    }
    return 1;
}
