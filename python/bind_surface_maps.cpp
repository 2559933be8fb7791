// The Python module: maps of surfaces: square geometry images, quad regions and their deformations, MAPS,
// polycubes, spheres.
#include "module_support.h"

#include "gimg/geometry/error.h"
#include "gimg/passes/maps.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/polycube.h"
#include "gimg/passes/quad_region.h"
#include "gimg/passes/sphere.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

namespace gimg::python {

void bind_surface_maps(py::module_& m) {
    m.def(
        "gim",
        [](Device* device, const Positions& positions, const Faces& faces, std::uint32_t size,
           const std::string& variant, std::size_t iterations, bool select, bool cut, const std::string& cut_graph) {
            const geo::Mesh input = to_mesh(positions, faces);
            const auto v = passes::parse_variant(variant);
            if (!v) throw geo::InputError("variant must be tutte, floater, stretch, density, uniform3d or curvature");
            passes::DiskCutOptions cut_options;
            if (cut_graph == "face-tree")
                cut_options.graph = geo::CutGraph::FaceTree;
            else if (cut_graph == "shortest-loops")
                cut_options.graph = geo::CutGraph::ShortestLoops;
            else if (cut_graph != "best")
                throw geo::InputError("cut_graph must be best, face-tree or shortest-loops");
            size = passes::geometry_image_size(size, input.vertex_count());
            std::optional<passes::DiskCut> disk;
            std::optional<passes::SeamBoundary> seam;  // both sides of the cut sampled alike, then joined
            bool seam_joined = false;
            passes::Parameterization map;
            passes::PositionImage image;
            geo::Mesh back;
            {
                py::gil_scoped_release release;
                Context* ctx = device ? &device->context() : nullptr;
                passes::ParameterizeOptions options{.variant = *v, .max_iterations = iterations};
                if (select) options.select_size = size;
                if (cut) {
                    passes::CutMap c = passes::cut_and_map(ctx, input, size, options, cut_options);
                    disk = std::move(c.cut);
                    seam = std::move(c.seam);
                    map = std::move(c.map);
                } else {
                    map = passes::parameterize_square(ctx, input, options);
                }
                const geo::Mesh& mesh = disk ? disk->disk : input;
                image = ctx ? passes::geometry_image_gpu(*ctx, mesh, map.uv, size)
                            : passes::geometry_image_cpu(mesh, map.uv, size);
                passes::SeamJoin join = passes::rebuild_over_seam(image, seam, [&](const passes::PositionImage& im) {
                    return ctx ? passes::reconstruct_gpu(*ctx, im) : passes::reconstruct_cpu(im);
                });
                back = std::move(join.mesh);
                seam_joined = join.joined;
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
            d["selected_iteration"] = map.selected;
            d["unsolved"] = map.unsolved.empty() ? py::object(py::none()) : py::cast(map.unsolved);
            d["flipped"] = passes::count_flipped(disk ? disk->disk : input, map.uv);
            if (disk) {
                // uv belongs to the opened mesh's vertices; source names the input vertex each copies
                // (-1 for one added on an edge).
                d["disk_positions"] = positions_array(disk->disk.positions);
                d["disk_faces"] = faces_array(disk->disk.triangles);
                py::array_t<std::int64_t> source(py::ssize_t(disk->source.size()));
                auto s = source.mutable_unchecked<1>();
                for (std::size_t i = 0; i < disk->source.size(); ++i)
                    s(py::ssize_t(i)) = disk->source[i] == geo::kInvalidIndex ? -1 : std::int64_t(disk->source[i]);
                d["source"] = source;
                d["cut_edges"] = disk->cut_edges;
                d["cut_paths"] = disk->paths;
                d["cut_graph"] = geo::cut_graph_name(disk->graph);
                d["seam_joined"] = seam_joined;
            }
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("size") = 0,
        py::arg("variant") = "curvature", py::arg("iterations") = 50, py::arg("select") = false, py::arg("cut") = false,
        py::arg("cut_graph") = "best",
        "A disk mesh's square map and N x N geometry image (gimg gim); device None runs the CPU twins; select "
        "returns the iterate whose image rebuilds the mesh best (gimg gim --select); cut opens any mesh into a "
        "disk first (gimg gim --cut), cut_graph is --cut-graph (best, face-tree or shortest-loops; with select, best "
        "maps "
        "both graphs and keeps the better image). Returns a dict: "
        "uv, image (N x N x 3), covered, positions and faces of the "
        "reconstruction, iterations, selected_iteration, flipped; with cut also disk_positions, disk_faces (the "
        "opened mesh uv belongs to), source (the input vertex of each, -1 for one added on an edge), cut_edges, "
        "cut_paths, cut_graph (the initial cut graph kept: face tree or shortest loops), seam_joined (the image's "
        "border pairs joined and the reconstruction closed over the seam)");
    m.def(
        "quadmap",
        [](Device* device, const Positions& positions, const Faces& faces, std::vector<std::uint32_t> corners,
           const std::string& weights, const std::string& start, const std::string& solver) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (corners.size() != 4) throw geo::InputError("corners: four vertex indices, counter-clockwise");
            if (weights != "floater" && weights != "chord") throw geo::InputError("weights must be floater or chord");
            if (start != "overrelaxed" && start != "dijkstra" && start != "flat")
                throw geo::InputError("start must be overrelaxed, dijkstra or flat");
            if (solver != "krylov" && solver != "iterate" && solver != "direct")
                throw geo::InputError("solver must be krylov, iterate or direct");
            const passes::QuadMapOptions o{
                .weights = weights == "chord" ? passes::QuadWeights::Chord : passes::QuadWeights::Floater,
                .start = start == "flat"       ? passes::QuadStart::Flat
                         : start == "dijkstra" ? passes::QuadStart::Dijkstra
                                               : passes::QuadStart::Overrelaxed,
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
        py::arg("start") = "overrelaxed", py::arg("solver") = "krylov",
        "A four-sided region's map onto the unit square (gimg quadmap). Returns a dict: the region's positions and "
        "faces (inserted points included), uv, original (the mesh's vertex per region vertex, -1 for an inserted "
        "point), iterations_u, iterations_v, flipped");
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
        "polycube",
        [](Device* device, const Positions& positions, const Faces& faces, double dz, double da, std::uint32_t k,
           const std::string& axis, bool map, double retry_seconds) {
            const geo::Mesh mesh = to_mesh(positions, faces);
            if (axis != "x" && axis != "y" && axis != "z" && axis != "auto")
                throw geo::InputError("axis must be x, y, z or auto");
            if (k < 1) throw geo::InputError("k must be at least 1");
            passes::PolycubeOptions o;
            o.dz = dz, o.da = da, o.k = k, o.map = map, o.retry_seconds = retry_seconds;
            o.axis = axis == "auto" ? 3 : std::uint8_t(axis[0] - 'x');
            passes::Polycube p;
            {
                py::gil_scoped_release release;
                p = passes::build_polycube(device ? &device->context() : nullptr, mesh, o);
            }
            const auto& s = p.stats;
            const std::string cut = s.retries_cut_short ? "; retries stopped at retry_seconds" : "";
            if (!s.polycube_valid) throw geo::InputError("the polycube is not valid (" + s.invalid_reason + ")" + cut);
            if (map && !s.mapped) throw geo::InputError("the map could not be built: " + s.map_note + cut);
            py::dict d;
            d["polycube"] = py::make_tuple(positions_array(p.surface.positions), faces_array(p.surface.triangles));
            py::array_t<std::uint8_t> hole(py::ssize_t(p.hole.size()));
            std::copy(p.hole.begin(), p.hole.end(), hole.mutable_data());
            d["hole"] = hole;
            if (map) d["mapped"] = positions_array(p.mapped);
            d["genus"] = s.genus, d["holes"] = s.holes, d["planes"] = s.planes, d["chains"] = s.chains;
            d["closed_by_bezier"] = s.closed_by_bezier, d["closed_by_fallback"] = s.closed_by_fallback;
            d["polycube_faces"] = s.polycube_faces, d["polycube_corners"] = s.polycube_corners;
            d["flips"] = s.flips, d["holes_marked"] = s.holes_marked;
            d["area_distortion"] = s.area_distortion, d["angle_distortion"] = s.angle_distortion;
            d["seconds"] = s.seconds;
            d["axis"] = std::string(1, char('x' + s.axis));
            d["attempts"] = s.attempts, d["max_level"] = s.max_level, d["slice_smoothing"] = s.slice_smoothing;
            return d;
        },
        py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("dz") = 0.0, py::arg("da") = 0.05,
        py::arg("k") = 2, py::arg("axis") = "auto", py::arg("map") = true, py::arg("retry_seconds") = 60.0,
        "Polycube of a closed or open mesh and the map onto it (gimg polycube): solves on the device (None: the CPU "
        "twins). Returns a dict: polycube (positions, faces), hole (per polycube face: 1 where the mesh's holes map), "
        "mapped (per mesh vertex, its point on the polycube; with map), and the statistics of docs/polycube.md");
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
}

}  // namespace gimg::python
