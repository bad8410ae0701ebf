#pragma once
// EXR files with any float channels and string attributes in the header, for the parts of a
// distributed render (render_part.h) that carry more than RGB. Writing is atomic, like image_io's.
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace volguide {

struct ExrLayers {
    int width = 0, height = 0;
    // Channel name -> width x height values, row-major, top row first; written as float32.
    std::map<std::string, std::vector<float>> channels;
    std::map<std::string, std::string> attributes;  // string header attributes
};

// Throws InputError naming the file.
void write_exr_layers(const std::string& path, const ExrLayers& layers);
// Every channel (read as float) and every string attribute.
ExrLayers read_exr_layers(const std::string& path);

}  // namespace volguide
