#include "volguide/render/render_part.h"

#include <stdexcept>

#include "volguide/core/error.h"
#include "volguide/render/exr_layers.h"

namespace volguide {

namespace {

constexpr const char* kRgb[3] = {"R", "G", "B"};
constexpr const char* kVariance[3] = {"variance.R", "variance.G", "variance.B"};

void put_image(ExrLayers& layers, const Image& image, const char* const names[3]) {
    for (int c = 0; c < 3; ++c) {
        std::vector<float>& values = layers.channels[names[c]];
        values.resize(image.pixels.size());
        for (size_t p = 0; p < image.pixels.size(); ++p) values[p] = image.pixels[p][c];
    }
}

bool has_image(const ExrLayers& layers, const char* const names[3]) {
    for (int c = 0; c < 3; ++c)
        if (!layers.channels.count(names[c])) return false;
    return true;
}

Image get_image(const ExrLayers& layers, const char* const names[3]) {
    Image image(layers.width, layers.height);
    for (int c = 0; c < 3; ++c) {
        const std::vector<float>& values = layers.channels.at(names[c]);
        for (size_t p = 0; p < image.pixels.size(); ++p) image.pixels[p][c] = values[p];
    }
    return image;
}

const std::string& attribute(const ExrLayers& layers, const std::string& path, const std::string& name) {
    const auto it = layers.attributes.find("volguide." + name);
    if (it == layers.attributes.end())
        throw InputError(SourceLocation{path, 0}, "not a part of a volguide render: no volguide." + name +
                                                      " attribute (parts are EXRs written by `volguide render` or `merge`)");
    return it->second;
}

}  // namespace

void write_part(const std::string& path, const RenderPart& part) {
    ExrLayers layers;
    layers.width = part.mean.width;
    layers.height = part.mean.height;
    put_image(layers, part.mean, kRgb);
    if (!part.variance.pixels.empty()) put_image(layers, part.variance, kVariance);
    std::vector<float>& w = layers.channels["W"];
    w.assign(part.weight.begin(), part.weight.end());
    const PartInfo& i = part.info;
    layers.attributes = {{"volguide.scene", i.scene},
                         {"volguide.scene_file", i.scene_file},
                         {"volguide.seed", std::to_string(i.seed)},
                         {"volguide.field", i.field},
                         {"volguide.integrator", i.integrator},
                         {"volguide.samples", format_ranges(i.samples)}};
    write_exr_layers(path, layers);
}

RenderPart read_part(const std::string& path) {
    const ExrLayers layers = read_exr_layers(path);
    const SourceLocation where{path, 0};
    if (!has_image(layers, kRgb)) throw InputError(where, "not a part of a volguide render: no R, G, B channels");
    if (!layers.channels.count("W"))
        throw InputError(where, "not a part of a volguide render: no W (filter weight) channel");
    RenderPart part;
    part.mean = get_image(layers, kRgb);
    if (has_image(layers, kVariance)) part.variance = get_image(layers, kVariance);
    const std::vector<float>& w = layers.channels.at("W");
    part.weight.assign(w.begin(), w.end());
    PartInfo& i = part.info;
    i.scene = attribute(layers, path, "scene");
    i.scene_file = attribute(layers, path, "scene_file");
    i.field = attribute(layers, path, "field");
    i.integrator = attribute(layers, path, "integrator");
    try {
        i.seed = std::stoull(attribute(layers, path, "seed"));
        i.samples = normalized(parse_ranges(attribute(layers, path, "samples")));
    } catch (const std::logic_error& e) {
        throw InputError(where, std::string("bad volguide metadata: ") + e.what());
    }
    return part;
}

}  // namespace volguide
