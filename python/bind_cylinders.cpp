// The Python module: geometry images: cylindrical (plain, hierarchical, in batches), position images, and back to meshes.
#include "module_support.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/sample.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>

namespace gimg::python {

namespace {

// The body of cylinder(): the mesh's frame, then one image of the GPU Z-buffer.
passes::CylinderImage project_cylinder(Context& ctx, const geo::Mesh& mesh, std::uint32_t width, std::uint32_t height,
                                       passes::CylinderFrame& frame) {
    frame = passes::fit_cylinder_frame(mesh);
    passes::CylinderZBuffer zbuffer(ctx, width, height);
    return zbuffer.project(zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frame)));
}

}  // namespace

void bind_cylinders(py::module_& m) {
    m.def(
        "cylinder",
        [](Device& device, const Positions& positions, const Faces& faces, std::uint32_t width, std::uint32_t height) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            passes::CylinderImage image;
            passes::CylinderFrame frame;
            {
                py::gil_scoped_release release;
                image = project_cylinder(device.context(), mesh, width, height, frame);
            }
            return cylinder_result(image, frame);
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width") = 256, py::arg("height") = 128,
        "The cylindrical geometry image on the GPU (gimg cylinder): (distance H x W, NaN where empty; mask; frame)");
    m.def(
        "cylinder_hierarchy",
        [](Device* device, const Positions& positions, const Faces& faces, std::uint32_t size, std::uint32_t base,
           double reach, const std::string& misses, std::optional<double> threshold) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            passes::check_hierarchy_sizes(base, size);
            if (!(reach >= 0.0)) throw geo::InputError("reach must be 0 (no limit) or more");
            const passes::HierarchyMiss miss = passes::hierarchy_miss(misses);
            passes::CylinderHierarchy h;
            passes::CylinderFrame frame;
            geo::Mesh finest;
            {
                py::gil_scoped_release release;
                frame = passes::fit_cylinder_frame(mesh);
                const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
                const passes::CylinderHierarchyOptions o{.base = base, .size = size, .reach = reach, .miss = miss};
                h = device ? passes::cylinder_hierarchy_gpu(device->context(), cyl, o)
                           : passes::cylinder_hierarchy_cpu(cyl, o);
                finest = passes::hierarchy_mesh(passes::decode_cylinder_hierarchy(h, h.levels()), frame, threshold);
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
        py::arg("reach") = 8.0, py::arg("misses") = "radial", py::arg("threshold") = py::none(),
        "The thesis's hierarchical cylindrical image (gimg cylinder --method hierarchical), rays on the device (None: "
        "the CPU, the same hierarchy): a dict with t and valid (size x size: 0 empty, 1 hit, 2 a miss kept on the "
        "surface, 3 a radial ray's hit), levels, the finest level's mesh (positions, faces; blocks with a side longer "
        "than "
        "threshold are holes: None twelve pitches, inf every block) and the frame");
    m.def(
        "cylinder_batch",
        [](Device& device, const py::list& meshes, std::uint32_t width, std::uint32_t height) {
            const std::vector<geo::Mesh> ms = to_meshes(meshes);
            std::vector<passes::CylinderFrame> frames;
            std::vector<passes::CylinderImage> images;
            {
                py::gil_scoped_release release;
                // Frames and cylinder meshes on every core, then one upload of them all.
                frames.resize(ms.size());
                std::vector<passes::CylinderMesh> cylinder_meshes(ms.size());
                geo::parallel_for_chunks(ms.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t i = begin; i < end; ++i) {
                        frames[i] = passes::fit_cylinder_frame(ms[i]);
                        cylinder_meshes[i] = passes::make_cylinder_mesh(ms[i], frames[i]);
                    }
                });
                passes::CylinderZBuffer zbuffer(device.context(), width, height);
                std::vector<passes::CylinderZBuffer::Job> jobs;
                for (const std::uint32_t id : zbuffer.add_meshes(cylinder_meshes)) jobs.push_back({id});
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
                passes::CylinderFrame frame;
                const passes::CylinderImage image = project_cylinder(device.context(), mesh, width, height, frame);
                back = passes::reconstruct_gpu(device.context(), image, frame);
                passes::check_rebuilt_surface(back, "the cylindrical image", "give it more pixels (width, height)");
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
                passes::CylinderFrame frame;
                const passes::CylinderImage image = project_cylinder(device.context(), mesh, width, height, frame);
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
            }
            std::sort(ms.begin(), ms.end());
            return ms.empty() ? 0.0 : ms[ms.size() / 2];
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("width"), py::arg("height"),
        py::arg("runs"));
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
}

}  // namespace gimg::python
