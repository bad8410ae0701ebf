// volguide._core: the compiled part of the `volguide` Python package (python/volguide/__init__.py
// re-exports it). See docs/python.md.
#include "bindings.h"

PYBIND11_MODULE(_core, m) {
    m.doc() = "volguide: zero-variance-based volume path guiding renderer (compiled core)";
    volguide::python::bind_errors(m);
    volguide::python::bind_images(m);
    volguide::python::bind_scene(m);
    volguide::python::bind_field(m);
    volguide::python::bind_distance(m);
}
