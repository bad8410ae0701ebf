// Library errors as Python exceptions: InputError (a scene, image or parameter problem with its
// file and line) -> volguide.SceneError(ValueError) with `file`, `line` and `message` attributes;
// FieldFormatError (a bad field file) -> volguide.FieldError(ValueError). std::invalid_argument
// and std::runtime_error keep pybind11's ValueError / RuntimeError.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "volguide/core/error.h"
#include "volguide/guiding/field_io.h"

namespace volguide::python {

namespace py = pybind11;

namespace {
// Type objects created once at import and owned by the module (never freed: the module lives
// until the interpreter ends).
PyObject* g_scene_error = nullptr;
PyObject* g_field_error = nullptr;
}  // namespace

void bind_errors(py::module_& m) {
    g_scene_error = PyErr_NewExceptionWithDoc(
        "volguide.SceneError",
        "A problem in a scene, image or parameter; `file`, `line` (0 = unknown) and `message` say where and what.",
        PyExc_ValueError, nullptr);
    g_field_error =
        PyErr_NewExceptionWithDoc("volguide.FieldError", "A guiding-field file that cannot be read.", PyExc_ValueError, nullptr);
    m.add_object("SceneError", py::handle(g_scene_error));
    m.add_object("FieldError", py::handle(g_field_error));
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            py::object error = py::reinterpret_borrow<py::object>(g_scene_error)(e.what());
            error.attr("file") = e.location().file;
            error.attr("line") = e.location().line;
            error.attr("message") = e.message();
            PyErr_SetObject(g_scene_error, error.ptr());
        } catch (const FieldFormatError& e) {
            PyErr_SetString(g_field_error, e.what());
        }
    });
}

}  // namespace volguide::python
