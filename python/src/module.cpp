// effigi._effigi: the compiled half of the Python package effigi (python/effigi/__init__.py
// is the other: keyword handling, the conformance wrapper, docs). Every effigi::Error
// becomes effigi.Error (a RuntimeError) with the same one-line message, file:line first.
#include "py_scene.hpp"
#include "schema_dict.hpp"

#include "image_io.hpp"  // apps/effigi: the CLI's image reader and PNG writer

#include "effigi/core/error.hpp"
#include "effigi/core/module.hpp"

#include <pybind11/stl.h>

namespace py = pybind11;
using effigi::python::PyScene;

namespace {

/// An H×W×3 float32 image from any object with the buffer protocol (C-contiguous).
void writePng(const std::string& path, const py::buffer& image) {
    const py::buffer_info b = image.request();
    if (b.format != py::format_descriptor<float>::format() || b.ndim != 3 || b.shape[2] != 3)
        effigi::fail("write_png: expected a height x width x 3 float32 array, got format '{}' with {} dimensions",
                     b.format, b.ndim);
    const py::ssize_t h = b.shape[0], w = b.shape[1];
    if (b.strides[2] != 4 || b.strides[1] != 12 || b.strides[0] != 12 * w)
        effigi::fail("write_png: the array must be C-contiguous");
    const auto* p = static_cast<const float*>(b.ptr);
    std::vector<float> rgb(p, p + std::size_t(h * w * 3));
    py::gil_scoped_release release;
    effigi::app::writePNG(path, int(w), int(h), rgb);
}

py::object readImage(const std::string& path) {
    effigi::Image img;
    {
        py::gil_scoped_release release;
        img = effigi::app::readRGB(path);
    }
    return effigi::python::handOver(std::move(img.pixels), img.height, img.width, 3, 3);
}

} // namespace

PYBIND11_MODULE(_effigi, m) {
    m.doc() = "effigi's compiled bindings; use the package effigi";
    py::register_exception<effigi::Error>(m, "Error", PyExc_RuntimeError);

    m.def("version", &effigi::version);
    m.def("_load_file", &PyScene::fromFile, py::arg("path"), py::arg("defines"), py::arg("spectral_bins"));
    m.def("_load_string", &PyScene::fromString, py::arg("xml"), py::arg("defines"), py::arg("spectral_bins"));
    m.def("components", &effigi::python::componentNames,
          "Every component the registry knows, as \"tag/name\" (built in or on EFFIGI_PLUGIN_PATH).");
    m.def("info", &effigi::python::schemaDict, py::arg("component"),
          "The schema of a component (\"bsdf/diffuse\") as a dict: doc, reference, parameters, ...");
    m.def("_read_image", &readImage, py::arg("path"));
    m.def("_write_png", &writePng, py::arg("path"), py::arg("image"));

    py::class_<PyScene>(m, "Scene", "A loaded scene (effigi.load_file / effigi.load_string).")
        .def("render", &PyScene::render, py::kw_only(), py::arg("spp") = py::none(), py::arg("seed") = 0,
             py::arg("threads") = 0, py::arg("space") = py::none(), py::arg("spectral") = false,
             py::arg("progress") = false,
             R"(Render the scene and return the image.

spp: samples per pixel (progressive passes, as `effigi render --spp`); default: the
     sampler's sample_count (as `effigi render`).
seed: added to the sampler's seed (`--seed`). threads: 0 = all cores (`-t`).
space: "srgb-linear" (or "srgb"), "rec2020", "acescg" (linear RGB) or "xyz"; default: the
       film's colorspace, i.e. what the CLI writes to its EXR.
spectral: return (H x W x N bin averages of spectral radiance, N bin centres in nm)
          instead; needs a film with spectral_bins (or load with spectral_bins=N).
progress: draw the CLI's progress bar on stderr.
Returns a float32 array of shape (height, width, 3) sharing the film's developed pixels.)")
        .def_property_readonly("size", &PyScene::size, "(width, height) of the rendered (crop) window")
        .def_property_readonly("renderer", &PyScene::rendererName)
        .def_property_readonly("spectral_bins", &PyScene::spectralBins)
        .def_property_readonly("colorspace", &PyScene::colorSpace, "the film's colour space, render()'s default")
        .def_property_readonly("source", &PyScene::source)
        .def_property_readonly("stats", &PyScene::stats,
                               "samples, rejected_samples, seconds, interrupted of the last render")
        .def("__repr__", &PyScene::repr);
}
