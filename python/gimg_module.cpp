// The Python module `gimg`: the library's capabilities on NumPy arrays (docs/python.md). Meshes go
// in as (positions N x 3 float, faces M x 3 int) and come out as float64 and int64 arrays; bad
// input raises ValueError with the command line's one-line message, machine failures
// gimg.DeviceError (a RuntimeError). The GIL is released while the library works.
#include "gimg/engine/context.h"
#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/maps.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/quad_region.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/retrieval.h"
#include "gimg/passes/render.h"
#include "gimg/passes/sample.h"
#include "gimg/passes/sphere.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>

namespace py = pybind11;
using namespace gimg;

namespace {

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// The mesh of two arrays, checked as the loaders check files.
geo::Mesh to_mesh(const Positions& positions, const Faces& faces) {
    if (positions.ndim() != 2 || positions.shape(1) != 3) throw geo::InputError("positions must be an N x 3 array");
    if (faces.ndim() != 2 || faces.shape(1) != 3)
        throw geo::InputError("faces must be an M x 3 array of vertex indices");
    geo::Mesh m;
    // Both arrays are C-contiguous (forcecast): read them as flat runs.
    static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));
    const auto n = std::size_t(positions.shape(0));
    m.positions.resize(n);
    if (n) std::memcpy(m.positions.data(), positions.data(), n * sizeof(glm::dvec3));
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(m.positions[i].x) || !std::isfinite(m.positions[i].y) || !std::isfinite(m.positions[i].z))
            throw geo::InputError("position " + std::to_string(i) + " is not finite");
    const std::int64_t* f = faces.data();
    const auto count = std::size_t(faces.shape(0));
    m.triangles.resize(count);
    for (std::size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            const std::int64_t id = f[3 * i + std::size_t(k)];
            if (id < 0 || std::uint64_t(id) >= n)
                throw geo::InputError("face " + std::to_string(i) + " names vertex " + std::to_string(id) + " of " +
                                      std::to_string(n));
            m.triangles[i][k] = std::uint32_t(id);
        }
    if (m.triangles.empty()) throw geo::InputError("the mesh has no faces");
    return m;
}

py::array_t<double> positions_array(const std::vector<glm::dvec3>& p) {
    py::array_t<double> out({py::ssize_t(p.size()), py::ssize_t(3)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i)
        for (int k = 0; k < 3; ++k) o(i, k) = p[std::size_t(i)][k];
    return out;
}

py::array_t<std::int64_t> faces_array(const std::vector<glm::uvec3>& t) {
    py::array_t<std::int64_t> out({py::ssize_t(t.size()), py::ssize_t(3)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i)
        for (int k = 0; k < 3; ++k) o(i, k) = t[std::size_t(i)][k];
    return out;
}

py::array_t<double> uv_array(const std::vector<glm::dvec2>& uv) {
    py::array_t<double> out({py::ssize_t(uv.size()), py::ssize_t(2)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i) o(i, 0) = uv[std::size_t(i)].x, o(i, 1) = uv[std::size_t(i)].y;
    return out;
}

py::dict position_image_dict(const passes::PositionImage& image) {
    py::array_t<float> xyz({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
    py::array_t<bool> covered({py::ssize_t(image.height), py::ssize_t(image.width)});
    auto x = xyz.mutable_unchecked<3>();
    auto c = covered.mutable_unchecked<2>();
    for (std::uint32_t b = 0; b < image.height; ++b)
        for (std::uint32_t a = 0; a < image.width; ++a) {
            const std::size_t o = image.index(a, b);
            for (int k = 0; k < 3; ++k) x(b, a, k) = image.xyz[3 * o + std::size_t(k)];
            c(b, a) = image.covered[o] != 0;
        }
    py::dict d;
    d["image"] = xyz;
    d["covered"] = covered;
    return d;
}

// The mesh's own parameters for `sample`: N x 2 in [0, 1]^2.
std::vector<glm::dvec2> to_uv(const py::array_t<double, py::array::c_style | py::array::forcecast>& uv, std::size_t n) {
    if (uv.ndim() != 2 || uv.shape(1) != 2 || std::size_t(uv.shape(0)) != n)
        throw geo::InputError("texture coordinates must be an N x 2 array, one row per vertex");
    const auto a = uv.unchecked<2>();
    std::vector<glm::dvec2> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = {a(py::ssize_t(i), 0), a(py::ssize_t(i), 1)};
        if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y))
            throw geo::InputError("texture coordinate " + std::to_string(i) + " is not finite");
    }
    return out;
}

// The vertex-per-pixel position image of an H x W x 3 array and an H x W mask.
passes::PositionImage to_position_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& xyz,
                                        const py::array_t<bool, py::array::c_style | py::array::forcecast>& covered) {
    if (xyz.ndim() != 3 || xyz.shape(2) != 3) throw geo::InputError("image must be an H x W x 3 array");
    if (covered.ndim() != 2 || covered.shape(0) != xyz.shape(0) || covered.shape(1) != xyz.shape(1))
        throw geo::InputError("covered must be an H x W array matching the image");
    passes::PositionImage image(std::uint32_t(xyz.shape(1)), std::uint32_t(xyz.shape(0)));
    const auto x = xyz.unchecked<3>();
    const auto c = covered.unchecked<2>();
    for (std::uint32_t b = 0; b < image.height; ++b)
        for (std::uint32_t a = 0; a < image.width; ++a) {
            const std::size_t o = image.index(a, b);
            image.covered[o] = c(b, a) ? 1 : 0;
            for (int k = 0; k < 3; ++k) image.xyz[3 * o + std::size_t(k)] = x(b, a, k);
        }
    return image;
}

// The Vulkan device, made once and reused by every call given it.
// A cylinder frame as a dict: rotation (3 x 3), translation, scale.
py::dict frame_dict(const passes::CylinderFrame& frame) {
    py::array_t<double> rotation({3, 3});
    auto r = rotation.mutable_unchecked<2>();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = frame.rotation[j][i];  // row i, column j
    py::dict f;
    f["rotation"] = rotation;
    f["translation"] = py::make_tuple(frame.translation.x, frame.translation.y, frame.translation.z);
    f["scale"] = frame.scale;
    return f;
}

// A cylindrical image and its frame as cylinder() returns them: (distance H x W, NaN where empty;
// mask; frame dict).
py::tuple cylinder_result(const passes::CylinderImage& image, const passes::CylinderFrame& frame) {
    const py::ssize_t height = image.height, width = image.width;
    py::array_t<float> distance({height, width});
    py::array_t<bool> mask({height, width});
    auto d = distance.mutable_unchecked<2>();
    auto k = mask.mutable_unchecked<2>();
    for (std::uint32_t v = 0; v < image.height; ++v)
        for (std::uint32_t u = 0; u < image.width; ++u) {
            d(v, u) = image.covered[image.index(u, v)] ? image.distance[image.index(u, v)] : NAN;
            k(v, u) = image.covered[image.index(u, v)] != 0;
        }
    return py::make_tuple(distance, mask, frame_dict(frame));
}

// A list of (positions, faces) pairs as meshes, each checked as to_mesh checks one.
std::vector<geo::Mesh> to_meshes(const py::list& meshes) {
    std::vector<geo::Mesh> out;
    for (const py::handle item : meshes) {
        const auto pair = item.cast<py::tuple>();
        if (pair.size() != 2) throw geo::InputError("meshes: a list of (positions, faces) pairs");
        out.push_back(to_mesh(pair[0].cast<Positions>(), pair[1].cast<Faces>()));
    }
    return out;
}

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

}  // namespace

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

    m.def(
        "load_mesh",
        [](const std::string& path) {
            const geo::Mesh mesh = geo::load_mesh(path);
            return py::make_tuple(positions_array(mesh.positions), faces_array(mesh.triangles));
        },
        py::arg("path"), "(positions N x 3, faces M x 3) of an OBJ, PLY, OFF or STL file");
    m.def(
        "save_mesh",
        [](const std::string& path, const Positions& positions, const Faces& faces) {
            geo::save_mesh(to_mesh(positions, faces), path);
        },
        py::arg("path"), py::arg("positions"), py::arg("faces"), "Writes .ply or .obj, whole or not at all");
    m.def(
        "info",
        [](const Positions& positions, const Faces& faces) {
            const geo::MeshInfo i = geo::analyze_topology(to_mesh(positions, faces));
            py::dict d;
            d["vertices"] = i.vertices, d["faces"] = i.faces, d["edges"] = i.edges, d["components"] = i.components;
            d["boundary_loops"] = i.boundary_loops, d["non_manifold_edges"] = i.non_manifold_edges;
            d["non_manifold_vertices"] = i.non_manifold_vertices, d["degenerate_faces"] = i.degenerate_faces;
            d["closed"] = i.closed, d["manifold"] = i.manifold, d["oriented"] = i.oriented;
            py::list genus;
            for (const auto& c : i.component_info) genus.append(c.genus ? py::cast(*c.genus) : py::none());
            d["genus"] = genus;
            return d;
        },
        py::arg("positions"), py::arg("faces"), "Counts, components, boundary loops, genus and defects (gimg info)");
    m.def(
        "cylinder",
        [](Device& device, const Positions& positions, const Faces& faces, std::uint32_t width, std::uint32_t height) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            passes::CylinderImage image;
            passes::CylinderFrame frame;
            {
                py::gil_scoped_release release;
                frame = passes::fit_cylinder_frame(mesh);
                passes::CylinderZBuffer zbuffer(device.context(), width, height);
                image = zbuffer.project(zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frame)));
            }
            return cylinder_result(image, frame);
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width") = 256, py::arg("height") = 128,
        "The cylindrical geometry image on the GPU (gimg cylinder): (distance H x W, NaN where empty; mask; frame)");
    m.def(
        "cylinder_hierarchy",
        [](Device* device, const Positions& positions, const Faces& faces, std::uint32_t size, std::uint32_t base,
           double reach) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            passes::check_hierarchy_sizes(base, size);
            if (!(reach >= 0.0)) throw geo::InputError("reach must be 0 (no limit) or more");
            passes::CylinderHierarchy h;
            passes::CylinderFrame frame;
            geo::Mesh finest;
            {
                py::gil_scoped_release release;
                frame = passes::fit_cylinder_frame(mesh);
                const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
                const passes::CylinderHierarchyOptions o{.base = base, .size = size, .reach = reach};
                h = device ? passes::cylinder_hierarchy_gpu(device->context(), cyl, o)
                           : passes::cylinder_hierarchy_cpu(cyl, o);
                finest = passes::hierarchy_mesh(passes::decode_cylinder_hierarchy(h, h.levels()), frame);
            }
            py::array_t<float> t({py::ssize_t(size), py::ssize_t(size)});
            py::array_t<std::uint8_t> valid({py::ssize_t(size), py::ssize_t(size)});
            std::memcpy(t.mutable_data(), h.t.data(), h.t.size() * sizeof(float));
            std::memcpy(valid.mutable_data(), h.valid.data(), h.valid.size());
            py::dict d;
            d["t"] = t, d["valid"] = valid, d["levels"] = h.levels();
            d["positions"] = positions_array(finest.positions);
            d["faces"] = faces_array(finest.triangles);
            d["frame"] = frame_dict(frame);
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("size") = 256, py::arg("base") = 32,
        py::arg("reach") = 2.0,
        "The thesis's hierarchical cylindrical image (gimg cylinder --method hierarchical), rays on the device (None: "
        "the CPU, the same hierarchy): a dict with t and valid (size x size: 0 empty, 1 hit, 2 a miss kept on the "
        "surface), levels, the finest level's mesh (positions, faces) and the frame");
    m.def(
        "cylinder_batch",
        [](Device& device, const py::list& meshes, std::uint32_t width, std::uint32_t height) {
            const std::vector<geo::Mesh> ms = to_meshes(meshes);
            std::vector<passes::CylinderFrame> frames;
            std::vector<passes::CylinderImage> images;
            {
                py::gil_scoped_release release;
                passes::CylinderZBuffer zbuffer(device.context(), width, height);
                std::vector<passes::CylinderZBuffer::Job> jobs;
                for (const geo::Mesh& mesh : ms) {
                    frames.push_back(passes::fit_cylinder_frame(mesh));
                    jobs.push_back({zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frames.back()))});
                }
                images = zbuffer.project(jobs);
            }
            py::list out;
            for (std::size_t i = 0; i < images.size(); ++i) out.append(cylinder_result(images[i], frames[i]));
            return out;
        },
        py::arg("device"), py::arg("meshes"), py::arg("width") = 256, py::arg("height") = 128,
        "cylinder() for a list of (positions, faces), projected in batches in one go: a list of its tuples");
    m.def(
        "roundtrip",
        [](Device& device, const Positions& positions, const Faces& faces, std::uint32_t width, std::uint32_t height,
           std::uint64_t samples) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            geo::Mesh back;
            geo::SurfaceDistance d;
            {
                py::gil_scoped_release release;
                const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
                passes::CylinderZBuffer zbuffer(device.context(), width, height);
                const passes::CylinderImage image =
                    zbuffer.project(zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frame)));
                back = passes::reconstruct_gpu(device.context(), image, frame);
                if (back.face_count() == 0) throw geo::InputError("the cylindrical image rebuilds no face");
                geo::SurfaceDistanceOptions o;
                if (samples) o.sampling.sample_count = samples;
                d = geo::surface_distance(mesh, back, o);
            }
            py::dict out;
            out["positions"] = positions_array(back.positions);
            out["faces"] = faces_array(back.triangles);
            out["rms_to_reconstruction"] = d.relative(d.a_to_b).rms;
            out["rms_back"] = d.relative(d.b_to_a).rms;
            out["hausdorff"] = d.relative(d.symmetric).max;
            out["bbox_diagonal"] = d.bbox_diagonal;
            return out;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width") = 256, py::arg("height") = 128,
        py::arg("samples") = 0,
        "Cylinder, reconstruction and their distance (gimg roundtrip): a dict with the reconstruction's positions and "
        "faces, rms_to_reconstruction, rms_back and hausdorff (relative to the diagonal), bbox_diagonal");
    py::class_<passes::ShapeDatabase>(m, "ShapeDatabase", "A retrieval index (gimg index)")
        .def_property_readonly("size", &passes::ShapeDatabase::size)
        .def_readonly("k", &passes::ShapeDatabase::k)
        .def_readonly("variance_kept", &passes::ShapeDatabase::variance_kept)
        .def_readonly("labels", &passes::ShapeDatabase::labels)
        .def("save",
             [](const passes::ShapeDatabase& db, const std::string& path) { passes::write_shape_database(path, db); })
        .def(
            "search",
            [](const passes::ShapeDatabase& db, Device& device, const Positions& positions, const Faces& faces,
               std::size_t k, const std::string& pose) {
                if (pose != "best-of-four" && pose != "aligned") throw geo::InputError("pose: best-of-four or aligned");
                const geo::Mesh mesh = to_mesh(positions, faces);
                std::vector<passes::ShapeMatch> matches;
                {
                    py::gil_scoped_release release;
                    const auto feature = passes::cylinder_features(device.context(), {mesh}, db.options).front();
                    matches = passes::search_shapes(
                        db, feature,
                        pose == "aligned" ? passes::PoseHandling::AsAligned : passes::PoseHandling::BestOfFour);
                }
                py::list out;
                for (std::size_t i = 0; i < matches.size() && i < k; ++i)
                    out.append(py::make_tuple(matches[i].model, matches[i].distance));
                return out;
            },
            py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("k") = 10,
            py::arg("pose") = "best-of-four",
            "The k models most like the mesh (gimg search): a list of (model index, distance), nearest first")
        .def(
            "evaluate",
            [](const passes::ShapeDatabase& db, Device& device, const py::list& meshes, const std::string& pose) {
                if (pose != "best-of-four" && pose != "aligned") throw geo::InputError("pose: best-of-four or aligned");
                const std::vector<geo::Mesh> ms = to_meshes(meshes);
                if (ms.size() != db.size()) throw geo::InputError("evaluate: the database's meshes, in its order");
                std::map<std::string, std::size_t> class_size;
                for (const auto& l : db.labels) ++class_size[l];
                passes::RetrievalScores total;
                std::size_t queries = 0;
                {
                    py::gil_scoped_release release;
                    const auto features = passes::cylinder_features(device.context(), ms, db.options);
                    for (std::size_t q = 0; q < ms.size(); ++q) {
                        const std::size_t relevant = class_size[db.labels[q]] - 1;
                        if (relevant == 0) continue;  // nothing to find
                        std::vector<std::string> ranked;
                        for (const auto& match : passes::search_shapes(
                                 db, features[q],
                                 pose == "aligned" ? passes::PoseHandling::AsAligned : passes::PoseHandling::BestOfFour,
                                 q))
                            ranked.push_back(db.labels[match.model]);
                        const passes::RetrievalScores r = passes::score_ranking(ranked, db.labels[q], relevant);
                        total.nearest_neighbour += r.nearest_neighbour, total.first_tier += r.first_tier;
                        total.second_tier += r.second_tier, total.dcg += r.dcg;
                        total.average_precision += r.average_precision;
                        ++queries;
                    }
                }
                if (queries == 0) throw geo::InputError("evaluate: no class has two models");
                py::dict d;
                d["nn"] = total.nearest_neighbour / double(queries),
                d["first_tier"] = total.first_tier / double(queries);
                d["second_tier"] = total.second_tier / double(queries), d["dcg"] = total.dcg / double(queries);
                d["map"] = total.average_precision / double(queries), d["queries"] = queries;
                return d;
            },
            py::arg("device"), py::arg("meshes"), py::arg("pose") = "best-of-four",
            "Leave-one-out scores over the database's own models (gimg eval): a dict with nn, first_tier, "
            "second_tier, dcg, map (means over the queries) and queries");
    m.def(
        "load_database", [](const std::string& path) { return passes::read_shape_database(path); }, py::arg("path"),
        "A database written by gimg index or ShapeDatabase.save");
    m.def(
        "index",
        [](Device& device, const py::list& meshes, std::vector<std::string> labels, std::uint32_t size,
           std::uint32_t reduced, double variance) {
            const std::vector<geo::Mesh> ms = to_meshes(meshes);
            if (!labels.empty() && labels.size() != ms.size()) throw geo::InputError("labels: one per mesh, or none");
            labels.resize(ms.size());
            std::vector<std::string> names(ms.size());
            for (std::size_t i = 0; i < ms.size(); ++i) names[i] = "model " + std::to_string(i);
            passes::RetrievalOptions o;
            o.size = size, o.reduced = reduced, o.variance = variance;
            if (o.reduced % 2 != 0 || o.size % o.reduced != 0)
                throw geo::InputError("size must be a multiple of reduced, and reduced even");
            py::gil_scoped_release release;
            return passes::build_shape_database(passes::cylinder_features(device.context(), ms, o), names, labels, o);
        },
        py::arg("device"), py::arg("meshes"), py::arg("labels") = std::vector<std::string>{}, py::arg("size") = 144,
        py::arg("reduced") = 48, py::arg("variance") = 0.95,
        "A retrieval index of a list of (positions, faces) (gimg index, the reduced-image descriptor): a "
        "ShapeDatabase");
    m.def(
        "_cylinder_ms_in_cpp",
        [](Device& device, const Positions& positions, const Faces& faces, std::uint32_t width, std::uint32_t height,
           std::uint32_t runs) {
            // The body of cylinder() timed inside C++ (no Python crossing, no arrays): what the
            // call-overhead figure of docs/python.md compares the Python call with.
            const geo::Mesh mesh = to_mesh(positions, faces);
            std::vector<double> ms;
            py::gil_scoped_release release;
            for (std::uint32_t r = 0; r < runs; ++r) {
                const auto t = std::chrono::steady_clock::now();
                const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
                passes::CylinderZBuffer zbuffer(device.context(), width, height);
                const passes::CylinderImage image =
                    zbuffer.project(zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frame)));
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
            }
            std::sort(ms.begin(), ms.end());
            return ms.empty() ? 0.0 : ms[ms.size() / 2];
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width"), py::arg("height"),
        py::arg("runs"));
    m.def(
        "gim",
        [](Device* device, const Positions& positions, const Faces& faces, std::uint32_t size,
           const std::string& variant, std::size_t iterations) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            const auto v = passes::parse_variant(variant);
            if (!v) throw geo::InputError("variant must be tutte, floater, stretch, density, uniform3d or curvature");
            passes::Parameterization map;
            passes::PositionImage image;
            geo::Mesh back;
            {
                py::gil_scoped_release release;
                Context* ctx = device ? &device->context() : nullptr;
                map = passes::parameterize_square(ctx, mesh, {.variant = *v, .max_iterations = iterations});
                image = ctx ? passes::geometry_image_gpu(*ctx, mesh, map.uv, size)
                            : passes::geometry_image_cpu(mesh, map.uv, size);
                back = ctx ? passes::reconstruct_gpu(*ctx, image) : passes::reconstruct_cpu(image);
            }
            py::array_t<float> xyz({py::ssize_t(size), py::ssize_t(size), py::ssize_t(3)});
            py::array_t<bool> covered({py::ssize_t(size), py::ssize_t(size)});
            auto x = xyz.mutable_unchecked<3>();
            auto c = covered.mutable_unchecked<2>();
            for (std::uint32_t b = 0; b < size; ++b)
                for (std::uint32_t a = 0; a < size; ++a) {
                    const std::size_t o = image.index(a, b);
                    for (int k = 0; k < 3; ++k) x(b, a, k) = image.xyz[3 * o + std::size_t(k)];
                    c(b, a) = image.covered[o] != 0;
                }
            py::dict d;
            d["uv"] = uv_array(map.uv);
            d["image"] = xyz;
            d["covered"] = covered;
            d["positions"] = positions_array(back.positions);
            d["faces"] = faces_array(back.triangles);
            d["iterations"] = map.iterations.size() - 1;
            d["flipped"] = map.iterations.back().flipped;
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("size") = 129,
        py::arg("variant") = "curvature", py::arg("iterations") = 50,
        "A disk mesh's square map and N x N geometry image (gimg gim); device None runs the CPU twins. Returns "
        "a dict: uv, image (N x N x 3), covered, positions and faces of the reconstruction, iterations, flipped");
    m.def(
        "quadmap",
        [](Device* device, const Positions& positions, const Faces& faces, std::vector<std::uint32_t> corners,
           const std::string& weights, const std::string& start, const std::string& solver) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (corners.size() != 4) throw geo::InputError("corners: four vertex indices, counter-clockwise");
            if (weights != "floater" && weights != "chord") throw geo::InputError("weights must be floater or chord");
            if (start != "dijkstra" && start != "flat") throw geo::InputError("start must be dijkstra or flat");
            if (solver != "krylov" && solver != "iterate" && solver != "direct")
                throw geo::InputError("solver must be krylov, iterate or direct");
            const passes::QuadMapOptions o{
                .weights = weights == "chord" ? passes::QuadWeights::Chord : passes::QuadWeights::Floater,
                .start = start == "flat" ? passes::QuadStart::Flat : passes::QuadStart::Dijkstra,
                .solver = solver == "iterate"  ? passes::QuadSolver::Iterate
                          : solver == "direct" ? passes::QuadSolver::Direct
                                               : passes::QuadSolver::Krylov};
            passes::QuadRegion region;
            passes::QuadMap map;
            {
                py::gil_scoped_release release;
                region = passes::cut_quad_region(mesh, {corners[0], corners[1], corners[2], corners[3]});
                map = passes::map_quad_region(device ? &device->context() : nullptr, region, o);
            }
            py::array_t<std::int64_t> original(py::ssize_t(region.original.size()));
            auto og = original.mutable_unchecked<1>();
            for (py::ssize_t i = 0; i < og.shape(0); ++i)
                og(i) = region.original[std::size_t(i)] == passes::kInsertedNode ? -1 : region.original[std::size_t(i)];
            py::dict d;
            d["positions"] = positions_array(region.mesh.positions);
            d["faces"] = faces_array(region.mesh.triangles);
            d["uv"] = uv_array(map.uv);
            d["original"] = original;
            d["iterations_u"] = map.iterations_u, d["iterations_v"] = map.iterations_v;
            d["flipped"] = map.flipped;
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("corners"), py::arg("weights") = "floater",
        py::arg("start") = "dijkstra", py::arg("solver") = "krylov",
        "A four-sided region's map onto the unit square (gimg quadmap). Returns a dict: the region's positions and "
        "faces (inserted points included), uv, original (the mesh's vertex per region vertex, -1 for an inserted "
        "point), iterations_u, iterations_v, flipped");
    m.def(
        "maps",
        [](Device* device, const Positions& positions, const Faces& faces, std::uint32_t levels, std::uint32_t base,
           const std::string& k, const std::string& flattening, double max_cone) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (levels < 1 || levels > 7) throw geo::InputError("levels must be 1 to 7");
            if (k != "lazy" && k != "0" && k != "1" && k != "2") throw geo::InputError("k must be lazy, 0, 1 or 2");
            if (flattening != "polar" && flattening != "za") throw geo::InputError("flattening must be polar or za");
            passes::MapsOptions o;
            o.base_vertices = base;
            o.flattening = flattening == "za" ? passes::RingFlattening::Za : passes::RingFlattening::Polar;
            o.max_cone = max_cone;
            passes::MapsRemesh r;
            std::vector<glm::dvec3> coefficients, coarse;
            {
                py::gil_scoped_release release;
                Context* ctx = device ? &device->context() : nullptr;
                r = passes::maps_remesh(ctx, mesh, o, levels);
                const passes::WaveletFilters filters = passes::wavelet_filters(r.remesh, k == "lazy" ? -1 : k[0] - '0');
                coefficients = coarse = r.remesh.positions;
                passes::wavelet_analysis(r.remesh, filters, coefficients);
                passes::wavelet_analysis(r.remesh, filters, coarse, levels - 1);
                coarse.resize(r.remesh.vertex_count[levels - 1]);
            }
            py::list meshes;
            for (std::uint32_t j = 0; j <= levels; ++j) {
                const geo::Mesh level = r.remesh.level_mesh(j);
                meshes.append(py::make_tuple(positions_array(level.positions), faces_array(level.triangles)));
            }
            py::dict d;
            d["base"] = py::make_tuple(positions_array(r.domain.base.positions), faces_array(r.domain.base.triangles));
            d["levels"] = meshes;
            d["coefficients"] = positions_array(coefficients);
            d["coarse"] = py::make_tuple(positions_array(coarse), faces_array(r.remesh.faces[levels - 1]));
            d["hierarchy_levels"] = r.domain.levels.size();
            d["fallbacks"] = r.fallbacks, d["unplaced"] = r.map.unplaced;
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("levels") = 4, py::arg("base") = 0,
        py::arg("k") = "1", py::arg("flattening") = "polar", py::arg("max_cone") = 2.0,
        "MAPS remesh of a closed mesh (gimg maps): points mapped on the device (None: the CPU twin), wavelets on the "
        "CPU. Returns a dict: base (positions, faces), levels (a (positions, faces) per level 0..J; level 0 is the "
        "base), coefficients (c^0 then every level's details, one row per vertex of level J), coarse (level J-1 one "
        "level down through the wavelets), hierarchy_levels, fallbacks, unplaced");
    m.def(
        "compare",
        [](const Positions& pa, const Faces& fa, const Positions& pb, const Faces& fb, std::uint64_t samples) {
            const geo::Mesh a = to_mesh(pa, fa), b = to_mesh(pb, fb);
            geo::SurfaceDistance d;
            {
                py::gil_scoped_release release;
                geo::SurfaceDistanceOptions o;
                if (samples) o.sampling.sample_count = samples;
                d = geo::surface_distance(a, b, o);
            }
            auto stats = [](const geo::DistanceStats& s) {
                py::dict x;
                x["mean"] = s.mean, x["rms"] = s.rms, x["max"] = s.max;
                return x;
            };
            py::dict out;
            out["a_to_b"] = stats(d.a_to_b), out["b_to_a"] = stats(d.b_to_a), out["symmetric"] = stats(d.symmetric);
            out["bbox_diagonal"] = d.bbox_diagonal;
            return out;
        },
        py::arg("positions_a"), py::arg("faces_a"), py::arg("positions_b"), py::arg("faces_b"), py::arg("samples") = 0,
        "Metro-style surface distance each way and symmetric (gimg compare); samples 0: max(1M, 10 per face)");
    m.def(
        "render",
        [](Device& device, const Positions& positions, const Faces& faces, std::uint32_t width, std::uint32_t height,
           double azimuth, double elevation, bool wireframe) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            geo::RgbaImage picture;
            {
                py::gil_scoped_release release;
                passes::RenderOptions o;
                o.width = width, o.height = height, o.wireframe = wireframe;
                o.view.azimuth_deg = azimuth, o.view.elevation_deg = elevation;
                picture = passes::render_mesh(device.context(), mesh, o);
            }
            py::array_t<std::uint8_t> out({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
            std::copy(picture.pixels.begin(), picture.pixels.end(), out.mutable_data());
            return out;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width") = 640, py::arg("height") = 480,
        py::arg("azimuth") = 35.0, py::arg("elevation") = 20.0, py::arg("wireframe") = false,
        "A picture of the mesh (gimg render): H x W x 4 uint8, alpha the covered share of each pixel");
    m.def(
        "sample",
        [](Device* device, const Positions& positions, const Faces& faces,
           const py::array_t<double, py::array::c_style | py::array::forcecast>& uv, std::uint32_t size) {
            geo::Mesh mesh = to_mesh(positions, faces);
            mesh.texcoords = to_uv(uv, mesh.vertex_count());
            passes::PositionImage image;
            {
                py::gil_scoped_release release;
                image = device ? passes::sample_gpu(device->context(), mesh, size) : passes::sample_cpu(mesh, size);
            }
            return position_image_dict(image);
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("uv"), py::arg("size") = 256,
        "A mesh sampled through its texture coordinates into a size x size position image (gimg sample); device "
        "None: the CPU reference. Returns a dict: image (H x W x 3), covered");
    m.def(
        "reconstruct",
        [](Device* device, const py::array_t<float, py::array::c_style | py::array::forcecast>& image,
           const py::array_t<bool, py::array::c_style | py::array::forcecast>& covered) {
            const passes::PositionImage pi = to_position_image(image, covered);
            geo::Mesh back;
            {
                py::gil_scoped_release release;
                back = device ? passes::reconstruct_gpu(device->context(), pi) : passes::reconstruct_cpu(pi);
            }
            return py::make_tuple(positions_array(back.positions), faces_array(back.triangles));
        },
        py::arg("device"), py::arg("image"), py::arg("covered"),
        "A position geometry image back to a mesh, each 2 x 2 block split along its shorter diagonal (gimg "
        "reconstruct); device None: the CPU reference");
    m.def(
        "sphere",
        [](Device* device, const Positions& positions, const Faces& faces, const std::string& method) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (method != "harmonic" && method != "kanai" && method != "gu" && method != "linear")
                throw geo::InputError("method must be harmonic, kanai, gu or linear");
            if (method == "harmonic" && !device) throw geo::InputError("the harmonic method runs on a device");
            passes::SphereResult r;
            passes::SphereMetrics metrics;
            {
                py::gil_scoped_release release;
                passes::check_sphere_input(mesh);
                r = method == "harmonic" ? passes::sphere_harmonic(device->context(), mesh)
                    : method == "kanai"  ? passes::sphere_kanai(mesh)
                    : method == "gu"     ? passes::sphere_gu(mesh)
                                         : passes::sphere_linear(mesh);
                metrics = passes::sphere_metrics(mesh, r.positions);
            }
            py::dict m2;
            m2["flips"] = metrics.flips, m2["conformal_energy"] = metrics.conformal_energy;
            m2["conformal_ratio"] = metrics.conformal_ratio, m2["area_distortion"] = metrics.area_distortion;
            m2["angle_distortion_mean_deg"] = metrics.angle_distortion_deg.mean;
            m2["angle_distortion_max_deg"] = metrics.angle_distortion_deg.max;
            m2["converged"] = r.converged;
            return py::make_tuple(positions_array(r.positions), m2);
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("method") = "harmonic",
        "A conformal map of a closed genus-0 mesh onto the unit sphere (gimg sphere): (points N x 3, metrics)");
    m.def(
        "reconstruct_cylinder",
        [](Device* device, const py::array_t<float, py::array::c_style | py::array::forcecast>& distance,
           const py::dict& frame, bool fill_caps) {
            if (distance.ndim() != 2) throw geo::InputError("distance must be an H x W array (NaN where empty)");
            passes::CylinderImage image(std::uint32_t(distance.shape(1)), std::uint32_t(distance.shape(0)));
            const auto d = distance.unchecked<2>();
            for (std::uint32_t v = 0; v < image.height; ++v)
                for (std::uint32_t u = 0; u < image.width; ++u) {
                    const float x = d(v, u);
                    image.covered[image.index(u, v)] = std::isnan(x) ? 0 : 1;
                    image.distance[image.index(u, v)] = std::isnan(x) ? 0.0f : x;
                }
            passes::CylinderFrame f;
            const auto r = py::cast<py::array_t<double, py::array::c_style | py::array::forcecast>>(frame["rotation"]);
            if (r.ndim() != 2 || r.shape(0) != 3 || r.shape(1) != 3) throw geo::InputError("frame rotation: 3 x 3");
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) f.rotation[j][i] = r.at(i, j);
            const auto t = py::cast<std::vector<double>>(frame["translation"]);
            if (t.size() != 3) throw geo::InputError("frame translation: three numbers");
            f.translation = {t[0], t[1], t[2]};
            f.scale = py::cast<double>(frame["scale"]);
            geo::Mesh back;
            {
                py::gil_scoped_release release;
                passes::ReconstructOptions o;
                o.fill_caps = fill_caps;
                back = device ? passes::reconstruct_gpu(device->context(), image, f, o)
                              : passes::reconstruct_cpu(image, f, o);
            }
            return py::make_tuple(positions_array(back.positions), faces_array(back.triangles));
        },
        py::arg("device"), py::arg("distance"), py::arg("frame"), py::arg("fill_caps") = false,
        "A cylindrical image (cylinder()'s distance and frame) back to a mesh in the model's coordinates (gimg "
        "reconstruct); device None: the CPU reference");
    m.def(
        "deform",
        [](Device* device, const Positions& positions, const Faces& faces, std::vector<std::uint32_t> corners,
           const py::object& offsets, double paste_height) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (corners.size() != 4) throw geo::InputError("corners: four vertex indices, counter-clockwise");
            const bool lattice = !offsets.is_none();
            passes::OffsetLattice l;
            if (lattice) {
                const auto o = py::cast<py::array_t<double, py::array::c_style | py::array::forcecast>>(offsets);
                if (o.ndim() != 3 || o.shape(2) != 3)
                    throw geo::InputError(
                        "offsets must be a Q x P x 3 array (rows in v, columns in u), in model units");
                l.rows = std::uint32_t(o.shape(0)), l.columns = std::uint32_t(o.shape(1));
                const auto a = o.unchecked<3>();
                for (py::ssize_t q = 0; q < a.shape(0); ++q)
                    for (py::ssize_t p = 0; p < a.shape(1); ++p)
                        l.offsets.push_back({a(q, p, 0), a(q, p, 1), a(q, p, 2)});
            } else if (paste_height == 0.0) {
                throw geo::InputError("deform takes offsets (a lattice) or paste_height (the built-in bump)");
            }
            geo::Mesh out;
            {
                py::gil_scoped_release release;
                const passes::QuadRegion region =
                    passes::cut_quad_region(mesh, {corners[0], corners[1], corners[2], corners[3]});
                Context* ctx = device ? &device->context() : nullptr;
                const passes::QuadMap map = passes::map_quad_region(ctx, region);
                const passes::PastedFeature bump{.scale = paste_height};
                out = lattice ? (ctx ? passes::deform_by_lattice_gpu(*ctx, mesh, region, map.uv, l)
                                     : passes::deform_by_lattice(mesh, region, map.uv, l))
                              : (ctx ? passes::paste_feature_gpu(*ctx, mesh, region, map.uv, bump)
                                     : passes::paste_feature(mesh, region, map.uv, bump));
            }
            return positions_array(out.positions);
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("corners"), py::arg("offsets") = py::none(),
        py::arg("paste_height") = 0.0,
        "The mesh's positions deformed through a quad region's map (gimg deform): a lattice of offsets (Q x P x 3, "
        "model units, the outer three rows and columns fixed) or the built-in bump of paste_height diagonals");
}
