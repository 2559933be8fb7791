// The Python module: meshes in and out: loading, saving, topology, distance and pictures.
#include "module_support.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/repair.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>

namespace gimg::python {

void bind_meshes(py::module_& m) {
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
        "repair",
        [](const Positions& positions, const Faces& faces, bool weld, bool largest) {
            geo::Mesh mesh = to_mesh(positions, faces);
            const geo::RepairReport r = geo::repair_mesh(mesh, {.weld = weld, .largest = largest});
            py::dict d;
            d["welded_vertices"] = r.welded_vertices, d["collapsed_faces"] = r.collapsed_faces;
            d["duplicate_faces"] = r.duplicate_faces, d["turned_faces"] = r.turned_faces;
            d["opened_edges"] = r.opened_edges, d["split_vertices"] = r.split_vertices;
            d["dropped_faces"] = r.dropped_faces, d["zero_area_faces"] = r.zero_area_faces;
            d["flipped_edges"] = r.flipped_edges, d["collapsed_edges"] = r.collapsed_edges;
            d["zero_area_left"] = r.zero_area_left, d["dropped_pieces"] = r.dropped_pieces;
            d["unused_vertices"] = r.unused_vertices, d["changed"] = r.changed();
            return py::make_tuple(positions_array(mesh.positions), faces_array(mesh.triangles), d);
        },
        py::arg("positions"), py::arg("faces"), py::arg("weld") = false, py::arg("largest") = false,
        "(positions, faces, report): the mesh made manifold and oriented, without collapsed, duplicate or "
        "zero-area faces (gimg repair)");
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
}

}  // namespace gimg::python
