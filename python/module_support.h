#pragma once
// What every part of the Python module shares: NumPy arrays to and from the library's types (checked
// as the loaders check files), and the Device object the functions take.
#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/reconstruct.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

namespace gimg::python {

namespace py = pybind11;

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// The mesh of two arrays, checked as the loaders check files.
geo::Mesh to_mesh(const Positions& positions, const Faces& faces);

py::array_t<double> positions_array(const std::vector<glm::dvec3>& p);

py::array_t<std::int64_t> faces_array(const std::vector<glm::uvec3>& t);

py::array_t<double> uv_array(const std::vector<glm::dvec2>& uv);

py::dict position_image_dict(const passes::PositionImage& image);

// The mesh's own parameters for `sample`: N x 2 in [0, 1]^2.
std::vector<glm::dvec2> to_uv(const py::array_t<double, py::array::c_style | py::array::forcecast>& uv, std::size_t n);

// The vertex-per-pixel position image of an H x W x 3 array and an H x W mask.
passes::PositionImage to_position_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& xyz,
                                        const py::array_t<bool, py::array::c_style | py::array::forcecast>& covered);

// A cylinder frame as a dict: rotation (3 x 3), translation, scale.
py::dict frame_dict(const passes::CylinderFrame& frame);

// A cylindrical image and its frame as cylinder() returns them: (distance H x W, NaN where empty;
// mask; frame dict).
py::tuple cylinder_result(const passes::CylinderImage& image, const passes::CylinderFrame& frame);

// A list of (positions, faces) pairs as meshes, each checked as to_mesh checks one.
std::vector<geo::Mesh> to_meshes(const py::list& meshes);

// The Vulkan device, made once and reused by every call given it.
class Device {
public:
    explicit Device(const std::string& name) {
        ContextOptions o = ContextOptions::from_environment();
        if (!name.empty()) o.device_filter = name;
        ctx_ = Context::create(o);
    }
    Context& context() { return *ctx_; }
    std::string name() const { return ctx_->device_info().name; }

private:
    std::unique_ptr<Context> ctx_;
};

// The module's functions, one group a file (bind_*.cpp).
void bind_meshes(py::module_& m);
void bind_cylinders(py::module_& m);
void bind_retrieval(py::module_& m);
void bind_surface_maps(py::module_& m);
void bind_batch(py::module_& m);

}  // namespace gimg::python
