// Images: read/write through the library's readers and writers (EXR, PNG), and the error metrics
// the benchmarks use.
#include <pybind11/pybind11.h>

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "arrays.h"
#include "bindings.h"
#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"

namespace volguide::python {

namespace {
// Mean over pixels and channels of (I - R)^2 / (R^2 + eps) in double, non-finite values of I left
// out (as compare_images does, which offers eps 1e-2 and 1e-3 only).
double relmse(const Image& image, const Image& reference, double eps) {
    if (image.width != reference.width || image.height != reference.height)
        throw std::invalid_argument(fmt::format("image {}x{} and reference {}x{} differ in size", image.width,
                                                image.height, reference.width, reference.height));
    double sum = 0;
    size_t n = 0;
    for (size_t p = 0; p < image.pixels.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double i = image.pixels[p][c], r = reference.pixels[p][c];
            if (!std::isfinite(i)) continue;
            sum += (i - r) * (i - r) / (r * r + eps);
            ++n;
        }
    return n ? sum / double(n) : 0.0;
}
}  // namespace

py::dict image_diff_dict(const ImageDiff& d) {
    py::dict out;
    out["relmse_1e-2"] = d.relmse_1e2;
    out["relmse_1e-3"] = d.relmse_1e3;
    out["relmse_1e-2_trimmed"] = d.relmse_1e2_trimmed;
    out["relmse_1e-3_trimmed"] = d.relmse_1e3_trimmed;
    out["mse"] = d.mse;
    out["mean"] = d.mean;
    out["reference_mean"] = d.reference_mean;
    out["nonfinite"] = d.nonfinite;
    out["pixels"] = d.pixels;
    return out;
}

void bind_images(py::module_& m) {
    m.def(
        "read_image", [](const std::string& path, bool raw) { return image_to_array(read_image(path, raw)); },
        py::arg("path"), py::arg("raw") = false,
        "Reads an EXR (linear) or PNG/JPEG (sRGB, converted to linear unless raw) image as a float32 (H, W, 3) array.");
    m.def(
        "write_image",
        [](const std::string& path, const FloatArray& image) { write_image(path, array_to_image(image, "image")); },
        py::arg("path"), py::arg("image"),
        "Writes an (H, W, 3) or (H, W) array as linear float EXR or sRGB PNG (by the extension), atomically.");
    m.def(
        "relmse",
        [](const FloatArray& image, const FloatArray& reference, double eps) {
            return relmse(array_to_image(image, "image"), array_to_image(reference, "reference"), eps);
        },
        py::arg("image"), py::arg("reference"), py::arg("eps") = 1e-2,
        "Relative MSE: mean over pixels and channels of (I - R)^2 / (R^2 + eps).");
    m.def(
        "compare_images",
        [](const FloatArray& image, const FloatArray& reference) {
            return image_diff_dict(compare_images(array_to_image(image, "image"), array_to_image(reference, "reference")));
        },
        py::arg("image"), py::arg("reference"),
        "All error metrics of `volguide diff` / the --stats 'reference' block, as a dict.");
}

}  // namespace volguide::python
