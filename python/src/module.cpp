// The compiled part of the Python package `gradmesh` (docs/python.md): convert, load, render and
// save through the library, with the GIL released while the library works.
#include <malloc.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "array_image.h"
#include "formats/atomic_file.h"
#include "formats/gmb.h"
#include "formats/raster.h"
#include "image_conversion.h"
#include "meshcore/error.h"
#include "meshcore/mesh_lines.h"
#include "meshcore/render.h"
#include "options.h"

namespace py = pybind11;

namespace gmpy {

namespace {

// A document and where it came from: the conversion it was made by (its image, for the report
// and a compact .gmb) or the file it was read from.
struct PyDocument {
    gm::Document doc;
    std::shared_ptr<const Conversion> conversion;  // null for a loaded document
    std::vector<std::string> inputs;               // files it was made from: never overwritten
    py::object report = py::none();                // the report dict, once asked for
};

int patchCount(const gm::Document& doc) {
    int n = 0;
    for (const gm::GradientMesh& m : doc.meshes) n += m.patchCount();
    return n;
}

int holeCount(const gm::Document& doc) {
    int n = 0;
    for (const gm::GradientMesh& m : doc.meshes) n += m.holeCount();
    return n;
}

// A path or an image array, as convert takes them: the array read while the GIL is held.
struct Source {
    std::string path;
    NamedImage image;
    bool isPath() const { return !path.empty(); }
};

Source sourceFrom(const py::object& object, const std::string& what, const char* arrayName,
                  uint64_t maxPixels) {
    if (py::isinstance<py::str>(object)) {
        Source s{object.cast<std::string>(), {}};
        if (s.path.empty()) throw py::value_error(what + " path is empty");
        return s;
    }
    py::array array = py::array::ensure(object);
    if (!array || array.dtype().kind() == 'O')
        throw py::type_error(what + " must be a path or a NumPy array, got " +
                             std::string(py::str(py::type::of(object).attr("__name__"))));
    Source s;
    s.image.image = arrayToImage(array, what, maxPixels);
    s.image.name = arrayName;
    return s;
}

PyDocument convert(const py::object& source, const py::object& mask, const py::dict& options) {
    const ImageJob job = parseImageJob(options, !mask.is_none());
    Source image = sourceFrom(source, "image", "<array>", job.maxPixels);
    Source maskSource;
    if (!mask.is_none()) maskSource = sourceFrom(mask, "mask", "<mask array>", job.maxPixels);
    PyDocument result;
    std::shared_ptr<Conversion> conversion;
    {
        py::gil_scoped_release release;
        if (image.isPath()) image.image = readImageFile(image.path, job.maxPixels);
        if (maskSource.isPath()) maskSource.image = readImageFile(maskSource.path, job.maxPixels);
        result.doc = convertImages(std::move(image.image), mask.is_none() ? nullptr : &maskSource.image,
                                   job, conversion);
    }
    result.conversion = std::move(conversion);
    for (const Source* s : {&image, &maskSource})
        if (s->isPath()) result.inputs.push_back(s->path);
    return result;
}

PyDocument load(const std::string& path, uint64_t maxPatches) {
    PyDocument result;
    {
        py::gil_scoped_release release;
        result.doc = readDocument(path, maxPatches);
    }
    result.inputs.push_back(path);
    return result;
}

py::bytes encode(const PyDocument& d, const std::string& path, const py::dict& options) {
    const gm::WriteOptions wo = parseWriteOptions(options);
    std::string bytes;
    {
        py::gil_scoped_release release;
        bytes = encodeForWriter(d.doc, d.conversion.get(), writerFor(path), path, wo);
    }
    return py::bytes(bytes);
}

size_t save(const PyDocument& d, const std::string& path, const py::dict& options) {
    const gm::WriteOptions wo = parseWriteOptions(options);
    py::gil_scoped_release release;
    const gm::MeshFormat& writer = writerFor(path);
    for (const std::string& input : d.inputs) requireDistinct(input, path);
    const std::string bytes = encodeForWriter(d.doc, d.conversion.get(), writer, path, wo);
    gm::writeFileAtomically(path, bytes);
    return bytes.size();
}

py::array render(const PyDocument& d, const py::dict& options) {
    const OptionReader o(options, "render", {"scale", "background", "mesh_lines", "dtype"});
    gm::RenderOptions ro;
    ro.scale = o.number("scale", 1.0, 0.01, 64);
    const std::array<float, 4> background = o.color("background", {0, 0, 0, 0});
    const std::array<float, 4> lines = o.color("mesh_lines", {0, 0, 0, 0});
    const std::string dtype = o.choice("dtype", "float32", {"float32", "uint8"}, "'float32' or 'uint8'");
    gm::RgbaImage image;
    {
        py::gil_scoped_release release;
        image = gm::renderDocument(d.doc, ro).image;
        gm::compositeOver(image, background);
        if (lines[3] > 0) gm::drawMeshLines(image, d.doc, ro.scale, lines);
    }
    if (dtype == "uint8") return imageToByteArray(image);
    return imageToFloatArray(std::move(image));
}

py::object report(PyDocument& d) {
    if (!d.report.is_none() || !d.conversion) return d.report;
    {
        std::string json;
        {
            py::gil_scoped_release release;
            json = conversionReport(d.doc, *d.conversion);
        }
        py::dict dict = py::module_::import("json").attr("loads")(json);
        dict["output"] = py::none();
        dict["bytes"].cast<py::dict>()["output"] = py::none();
        d.report = dict;
    }
    return d.report;
}

// Pickled as its lossless .gmb and its report (the image it was converted from is left out).
py::tuple pickleState(PyDocument& d) {
    const py::object r = report(d);
    std::string bytes;
    {
        py::gil_scoped_release release;
        bytes = gm::encodeGmb(d.doc, false);
    }
    return py::make_tuple(py::bytes(bytes), r, py::cast(d.inputs));
}

PyDocument unpickle(const py::tuple& state) {
    if (state.size() != 3) throw std::runtime_error("not a pickled gradmesh.Document");
    PyDocument d;
    d.doc = gm::decodeGmb(state[0].cast<std::string>(), gm::ReadLimits{});
    d.report = state[1];
    d.inputs = state[2].cast<std::vector<std::string>>();
    return d;
}

std::string describe(const PyDocument& d) {
    return "<gradmesh.Document " + std::to_string(d.doc.width) + "x" + std::to_string(d.doc.height) +
           ", " + std::to_string(d.doc.meshes.size()) + " meshes, " + std::to_string(patchCount(d.doc)) +
           " patches>";
}

void registerErrors(py::module_& m) {
    static py::exception<gm::Error> error(m, "Error", PyExc_RuntimeError);
    error.doc() = "A failure with an input or output: the message is the CLI's; file, where and "
                  "reason give its parts.";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const gm::Error& e) {
            py::object instance = py::handle(error.ptr())(messageLine(e.what()));
            instance.attr("file") = e.file().empty() ? py::object(py::none()) : py::str(e.file());
            instance.attr("where") = e.where().empty() ? py::object(py::none()) : py::str(e.where());
            instance.attr("reason") = py::str(e.reason());
            PyErr_SetObject(error.ptr(), instance.ptr());
        }
    });
}

}  // namespace

}  // namespace gmpy

PYBIND11_MODULE(_gradmesh, m) {
    using namespace gmpy;
    // As the CLI does: conversions allocate and free the same large buffers on every step, which
    // glibc would otherwise hand back to the kernel each time.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    m.doc() = "gradmesh's compiled core; use the gradmesh package";
    registerErrors(m);

    py::class_<PyDocument>(m, "Document", "Gradient meshes on a canvas: a conversion's or a file's.")
        .def_property_readonly("width", [](const PyDocument& d) { return d.doc.width; })
        .def_property_readonly("height", [](const PyDocument& d) { return d.doc.height; })
        .def_property_readonly("meshes", [](const PyDocument& d) { return d.doc.meshes.size(); },
                               "number of meshes")
        .def_property_readonly("shapes", [](const PyDocument& d) { return d.doc.shapes.size(); },
                               "number of flat shapes (regions of one colour)")
        .def_property_readonly("patches", [](const PyDocument& d) { return patchCount(d.doc); })
        .def_property_readonly("holes", [](const PyDocument& d) { return holeCount(d.doc); })
        .def_property_readonly("report", &report,
                               "the conversion's report (convert --report R.json) as a dict; None "
                               "for a loaded document")
        .def("_save", &save)
        .def("_encode", &encode)
        .def("_render", &render)
        .def("__repr__", &describe)
        .def(py::pickle(&pickleState, &unpickle));

    m.def("_convert", &convert, py::arg("source"), py::arg("mask"), py::arg("options"));
    m.def("_load", &load, py::arg("path"), py::arg("max_document_patches"));
    m.def(
        "_read_image",
        [](const std::string& path, uint64_t maxPixels) {
            NamedImage image;
            {
                py::gil_scoped_release release;
                image = readImageFile(path, maxPixels);
            }
            return imageToFloatArray(std::move(image.image));
        },
        py::arg("path"), py::arg("max_pixels"));
    m.attr("MAX_DOCUMENT_PATCHES") = gm::ReadLimits{}.maxPatches;
    m.attr("MAX_PIXELS") = ImageJob{}.maxPixels;
}
