// The Python module: any function of a mesh over a list of meshes (gimg batch's run of a collection).
#include "module_support.h"

#include "gimg/geometry/error.h"

#include <string>

namespace gimg::python {

namespace {

// One item of the list as (positions, faces): a pair as it is, a path read by load_mesh.
py::tuple mesh_of(const py::handle item, const py::module_& gimg) {
    if (py::isinstance<py::str>(item) || py::hasattr(item, "__fspath__"))
        return gimg.attr("load_mesh")(py::module_::import("os").attr("fspath")(item));
    const auto pair = py::reinterpret_borrow<py::object>(item);
    if (!py::isinstance<py::tuple>(pair) && !py::isinstance<py::list>(pair))
        throw geo::InputError("meshes: a list of (positions, faces) pairs or mesh file paths");
    const auto t = py::tuple(pair);
    if (t.size() != 2) throw geo::InputError("meshes: a list of (positions, faces) pairs or mesh file paths");
    return t;
}

// The batched projection applies when only the device and the image size are given.
bool projects_together(const py::function& function, const py::kwargs& options, const py::module_& gimg) {
    if (!function.is(gimg.attr("cylinder"))) return false;
    for (const auto& [key, value] : options) {
        const auto name = key.cast<std::string>();
        if (name != "device" && name != "width" && name != "height") return false;
    }
    return options.contains("device");
}

}  // namespace

void bind_batch(py::module_& m) {
    m.def(
        "batch",
        [](const py::function& function, const py::iterable& meshes, const std::string& errors,
           const py::kwargs& options) {
            if (errors != "raise" && errors != "keep") throw geo::InputError("errors must be \"raise\" or \"keep\"");
            const bool keep = errors == "keep";
            const auto gimg = py::module_::import("gimg");
            py::list out;
            std::vector<py::object> items;
            for (const py::handle item : meshes) items.push_back(py::reinterpret_borrow<py::object>(item));
            // cylinder: one batched projection (bit for bit the single calls); a failure there, with
            // errors kept, falls back to the call per mesh below.
            if (projects_together(function, options, gimg)) {
                try {
                    py::list list;
                    for (const py::object& item : items) list.append(mesh_of(item, gimg));
                    return py::list(gimg.attr("cylinder_batch")(py::arg("meshes") = list, **options));
                } catch (const py::error_already_set& e) {
                    if (!keep || !(e.matches(PyExc_ValueError) || e.matches(PyExc_OSError))) throw;
                } catch (const geo::InputError&) {
                    if (!keep) throw;
                }
            }
            for (const py::object& item : items) {
                try {
                    const py::tuple mesh = mesh_of(item, gimg);
                    out.append(function(py::arg("positions") = mesh[0], py::arg("faces") = mesh[1], **options));
                } catch (py::error_already_set& e) {
                    // Bad input and unreadable files are this mesh's own; a lost device ends the run.
                    if (!keep || !(e.matches(PyExc_ValueError) || e.matches(PyExc_OSError))) throw;
                    out.append(e.value());
                } catch (const geo::InputError& e) {
                    if (!keep) throw;
                    out.append(py::module_::import("builtins").attr("ValueError")(e.what()));
                }
            }
            return out;
        },
        py::arg("function"), py::arg("meshes"), py::arg("errors") = "raise",
        "function(positions=, faces=, **options) for each mesh of a list of (positions, faces) pairs or mesh file "
        "paths: a list of the results in order. errors=\"keep\" puts a failing mesh's ValueError or OSError in its "
        "place and goes on (a DeviceError still ends the run); cylinder with only device, width and height projects "
        "the list in one batch (cylinder_batch)");
}

}  // namespace gimg::python
