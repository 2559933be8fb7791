// The Python module `gimg`: the library's capabilities on NumPy arrays (docs/python.md). Meshes go
// in as (positions N x 3 float, faces M x 3 int) and come out as float64 and int64 arrays; bad
// input raises ValueError with the command line's one-line message, machine failures
// gimg.DeviceError (a RuntimeError). The GIL is released while the library works.
#include "module_support.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"

using namespace gimg;
using namespace gimg::python;

PYBIND11_MODULE(gimg, m) {
    m.doc() = "gimg: triangle meshes to geometry images and parameterizations, and back, on Vulkan";
    static py::exception<gimg::Error> device_error(m, "DeviceError", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const geo::InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const gimg::Error& e) {
            if (e.is_input_error())
                PyErr_SetString(PyExc_ValueError, e.what());
            else
                device_error(e.what());
        } catch (const geo::EnvironmentError& e) {
            PyErr_SetString(PyExc_OSError, e.what());
        }
    });

    py::class_<Device>(m, "Device", "A Vulkan device (GIMG_DEVICE and GIMG_VALIDATION apply), reused across calls")
        .def(py::init<const std::string&>(), py::arg("name") = "",
             "name: part of the device's name (default: the one gimg prefers)")
        .def_property_readonly("name", &Device::name);

    bind_meshes(m);
    bind_cylinders(m);
    bind_retrieval(m);
    bind_surface_maps(m);
    bind_batch(m);
}
