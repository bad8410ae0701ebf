#pragma once
// Conversions between numpy arrays and the library's images and vectors (copies: the library keeps
// its own storage, and arrays handed to Python own theirs).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/image.h"
#include "volguide/core/vec.h"

namespace volguide::python {

namespace py = pybind11;
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// (H, W, 3) float32, top row first (the library's row order).
py::array_t<float> image_to_array(const Image& image);
// From (H, W, 3) (or (H, W) grey); throws ValueError for other shapes.
Image array_to_image(const FloatArray& array, const char* name);
// (N, 3) or (3,) -> N vectors; throws ValueError naming `name` otherwise.
std::vector<Vec3f> to_vectors(const FloatArray& array, const char* name);
// Pairs two vector lists of equal length, or repeats a single vector to the other's length.
void broadcast_pair(std::vector<Vec3f>& a, std::vector<Vec3f>& b, const char* name_a, const char* name_b);
// N colours -> (N, 3) float32.
py::array_t<float> colors_to_array(const std::vector<Color3>& colors);

}  // namespace volguide::python
