#include "arrays.h"

#include <fmt/format.h>

#include <cstring>

namespace volguide::python {

static_assert(sizeof(Color3) == 3 * sizeof(float), "Color3 must be three packed floats");

py::array_t<float> image_to_array(const Image& image) {
    py::array_t<float> out({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
    if (!image.pixels.empty())
        std::memcpy(out.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(Color3));
    return out;
}

Image array_to_image(const FloatArray& array, const char* name) {
    const bool rgb = array.ndim() == 3 && array.shape(2) == 3;
    if (!rgb && array.ndim() != 2)
        throw py::value_error(fmt::format("{} must be an (H, W, 3) or (H, W) array", name));
    Image image(int(array.shape(1)), int(array.shape(0)));
    const float* src = array.data();
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = rgb ? Color3(src[3 * i], src[3 * i + 1], src[3 * i + 2]) : Color3(src[i]);
    return image;
}

std::vector<Vec3f> to_vectors(const FloatArray& array, const char* name) {
    const bool single = array.ndim() == 1 && array.shape(0) == 3;
    if (!single && !(array.ndim() == 2 && array.shape(1) == 3))
        throw py::value_error(fmt::format("{} must be an (N, 3) or (3,) array", name));
    const size_t n = single ? 1 : size_t(array.shape(0));
    std::vector<Vec3f> out(n);
    const float* src = array.data();
    for (size_t i = 0; i < n; ++i) out[i] = Vec3f(src[3 * i], src[3 * i + 1], src[3 * i + 2]);
    return out;
}

void broadcast_pair(std::vector<Vec3f>& a, std::vector<Vec3f>& b, const char* name_a, const char* name_b) {
    if (a.size() == b.size()) return;
    if (a.size() == 1) a.assign(b.size(), a[0]);
    else if (b.size() == 1) b.assign(a.size(), b[0]);
    else throw py::value_error(fmt::format("{} ({}) and {} ({}) differ in length", name_a, a.size(), name_b, b.size()));
}

py::array_t<float> colors_to_array(const std::vector<Color3>& colors) {
    py::array_t<float> out({py::ssize_t(colors.size()), py::ssize_t(3)});
    if (!colors.empty()) std::memcpy(out.mutable_data(), colors.data(), colors.size() * sizeof(Color3));
    return out;
}

}  // namespace volguide::python
