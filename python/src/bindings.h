#pragma once
// The module's parts, one function per concept, called from module.cpp.
#include <pybind11/pybind11.h>

namespace volguide {
struct ImageDiff;
}

namespace volguide::python {

// An ImageDiff as the dict of the --stats 'reference' block (bind_images.cpp).
pybind11::dict image_diff_dict(const ImageDiff& diff);

void bind_errors(pybind11::module_& m);
void bind_images(pybind11::module_& m);
void bind_scene(pybind11::module_& m);
void bind_field(pybind11::module_& m);
void bind_distance(pybind11::module_& m);  // Field.distance_pdf (after bind_field)

}  // namespace volguide::python
