// A surface cut open into a disk for the square map: the initial cut (or a seam), then paths toward
// the stretch of Floater's map, as Gu, Gortler and Hoppe (2002) augment theirs.
#include "gimg/geometry/disk_cut.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/parameterize.h"
#include "parameterize/reweighting.h"

#include <glm/geometric.hpp>

#include <chrono>
#include <exception>

namespace gimg::passes {

namespace {

struct Opened {
    geo::OpenedMesh mesh;
    std::size_t split_edges = 0;
    std::vector<glm::dvec2> uv;  // Floater's map
    std::size_t flipped = 0;     // its triangles turned over: regions crushed below what doubles resolve
    double l2_stretch = 0.0;     // infinite with any turned triangle
};

// Fewer turned triangles, or as many and the stretch lower by `fall`.
bool better(const Opened& a, const Opened& b, double fall) {
    return a.flipped < b.flipped || (a.flipped == b.flipped && a.l2_stretch < b.l2_stretch * (1.0 - fall));
}

Opened open_and_map(Context* ctx, const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                    const std::vector<std::uint8_t>& cut) {
    Opened o;
    o.mesh = geo::open_along(mesh, adj, cut);
    o.split_edges = geo::split_dividing_edges(o.mesh) + geo::split_short_boundary(o.mesh);
    // A cut that leaves no disk is this code's fault, not the input's: the input was checked.
    const geo::MeshInfo info = geo::analyze_topology(o.mesh.disk);
    if (info.components != 1 || info.boundary_loops != 1 || info.component_info[0].euler_characteristic != 1)
        throw std::logic_error("cut_to_disk: the cut did not open the surface into a disk");
    ParameterizeOptions floater;
    floater.variant = ParameterizeVariant::Floater;
    Parameterization p;
    try {
        p = parameterize_square(ctx, o.mesh.disk, floater);
    } catch (const geo::InputError& e) {
        throw geo::InputError(std::string("cutting the mesh open: Floater's map of the cut surface failed: ") +
                              e.what());
    }
    o.uv = p.uv;
    o.flipped = p.iterations.front().flipped;
    o.l2_stretch = p.iterations.front().l2_stretch;
    return o;
}

// A cut with the paths toward the stretch that serve it best: every path is tried; the cut kept is
// the one of the first k paths whose map is best.
struct Augmented {
    std::vector<std::uint8_t> cut;
    Opened opened;
    std::size_t paths = 0;
    std::vector<double> l2_stretch;  // of the start, then with each path tried
};

Augmented augment(Context* ctx, const geo::Mesh& mesh, const geo::MeshAdjacency& adj, std::vector<std::uint8_t> cut,
                  const DiskCutOptions& options) {
    Opened last = open_and_map(ctx, mesh, adj, cut);
    Augmented best{cut, last, 0, {last.l2_stretch}};
    for (std::size_t k = 1; k <= options.max_paths; ++k) {
        // The vertex of largest stretch, where Floater's map crushes the surface most, and of those
        // (turned triangles have infinite stretch) the farthest from the cut.
        const geo::Mesh& disk = last.mesh.disk;
        const std::vector<double> face_area = geo::face_areas(disk);
        const std::vector<double> stretch = detail::vertex_stretch(
            geo::build_adjacency(disk), detail::face_stretch_squared(disk, last.uv, face_area), face_area);
        const geo::PathTree tree = geo::shortest_paths(mesh, adj, geo::cut_vertices(adj, cut));
        const auto source = [&](std::size_t v) { return last.mesh.source[v]; };
        std::size_t worst = stretch.size();
        for (std::size_t v = 0; v < stretch.size(); ++v)
            if (source(v) != geo::kInvalidIndex && tree.distance[source(v)] > 0.0 &&
                (worst == stretch.size() || stretch[v] > stretch[worst] ||
                 (stretch[v] == stretch[worst] && tree.distance[source(v)] > tree.distance[source(worst)])))
                worst = v;
        if (worst == stretch.size()) break;  // every vertex on the cut
        geo::add_path(adj, tree, source(worst), cut);
        geo::zip_closed_in(mesh, adj, cut);
        last = open_and_map(ctx, mesh, adj, cut);
        best.l2_stretch.push_back(last.l2_stretch);
        if (better(last, best.opened, options.stop_fall)) {
            best.opened = last;
            best.cut = cut;
            best.paths = k;
        }
    }
    return best;
}

}  // namespace

DiskCut cut_to_disk(Context* ctx, const geo::Mesh& mesh, const DiskCutOptions& options) {
    check_cuttable_mesh(mesh);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const auto start = [&](geo::CutGraph kind) {
        std::vector<std::uint8_t> cut = geo::initial_cut(mesh, adj, kind);
        // A closed genus-0 surface: the tree of faces crosses every edge it leaves.
        bool open = false;
        for (std::size_t e = 0; e < cut.size() && !open; ++e) open = cut[e] || adj.edge_face_count(e) == 1;
        if (!open) geo::add_seam(mesh, adj, cut);
        geo::zip_closed_in(mesh, adj, cut);
        return cut;
    };
    // Both initial cuts where they differ (a surface of higher genus or with several holes), kept by
    // the same rule as the paths. Neither the shorter cut nor the lower stretch wins on every mesh.
    DiskCut out;
    out.graph = options.graph.value_or(geo::CutGraph::FaceTree);
    const std::vector<std::uint8_t> first = start(out.graph);
    Augmented best = augment(ctx, mesh, adj, first, options);
    out.tried = best.l2_stretch.size();
    const std::vector<std::uint8_t> loops = options.graph ? first : start(geo::CutGraph::ShortestLoops);
    if (loops != first) {
        Augmented other = augment(ctx, mesh, adj, loops, options);
        out.tried += other.l2_stretch.size();
        out.graph_l2_stretch = {best.opened.l2_stretch, other.opened.l2_stretch};
        if (better(other.opened, best.opened, 0.0)) {
            best = std::move(other);
            out.graph = geo::CutGraph::ShortestLoops;
        }
    }
    if (best.opened.flipped)
        throw geo::InputError("cutting the mesh open: the best of " + std::to_string(out.tried) +
                              " cuts tried still turns " + std::to_string(best.opened.flipped) +
                              " triangles over in Floater's map (parts crushed below what doubles resolve, "
                              "even solved to 1e-11; more --cut-paths may free them)");
    const std::vector<std::uint8_t>& cut = best.cut;
    out.paths = best.paths;
    out.l2_stretch = std::move(best.l2_stretch);
    out.disk = std::move(best.opened.mesh.disk);
    out.source = std::move(best.opened.mesh.source);
    out.split_edges = best.opened.split_edges;
    out.cut_degree.assign(mesh.vertex_count(), 0);
    for (std::size_t e = 0; e < cut.size(); ++e)
        if (cut[e] || adj.edge_face_count(e) == 1)
            ++out.cut_degree[adj.edges[2 * e]], ++out.cut_degree[adj.edges[2 * e + 1]];
    for (std::size_t e = 0; e < cut.size(); ++e)
        if (cut[e]) {
            ++out.cut_edges;
            out.cut_length += glm::distance(mesh.positions[adj.edges[2 * e]], mesh.positions[adj.edges[2 * e + 1]]);
        }
    return out;
}

CutMap cut_and_map(Context* ctx, const geo::Mesh& mesh, std::uint32_t size, const ParameterizeOptions& options,
                   const DiskCutOptions& cut_options) {
    auto run = [&](const DiskCutOptions& co) {
        CutMap r;
        const auto start = std::chrono::steady_clock::now();
        r.cut = cut_to_disk(ctx, mesh, co);
        r.cut_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        r.seam = seam_boundary(r.cut, size);
        ParameterizeOptions po = options;
        if (r.seam) po.boundary = r.seam->boundary;
        if (r.cut.cut_edges > 0) {
            po.rise_ends_run = false;
            po.candidates_size = size;
        }
        r.map = parameterize_square(ctx, r.cut.disk, po);
        return r;
    };
    check_cuttable_mesh(mesh);
    // The two initial graphs differ where the surface is neither a sphere nor a disk (Euler
    // characteristic 0 or less): with select, each is cut and mapped once, and the better image kept.
    if (options.select_size == 0 || cut_options.graph ||
        geo::analyze_topology(mesh).component_info.at(0).euler_characteristic > 0)
        return run(cut_options);
    std::vector<CutMap> maps;
    std::exception_ptr refused;
    for (geo::CutGraph graph : {geo::CutGraph::FaceTree, geo::CutGraph::ShortestLoops}) {
        DiskCutOptions co = cut_options;
        co.graph = graph;
        try {
            maps.push_back(run(co));
        } catch (const geo::InputError&) {
            refused = std::current_exception();  // this graph's cut turns triangles over
        }
    }
    if (maps.empty()) std::rethrow_exception(refused);
    if (maps.size() == 1) return std::move(maps.front());
    auto rms = [](const CutMap& c) { return c.map.iterations[c.map.selected].image_rms; };
    auto stretch = [](const CutMap& c) { return c.cut.l2_stretch[c.cut.paths]; };
    std::vector<double> image_rms{rms(maps[0]), rms(maps[1])}, graph_stretch{stretch(maps[0]), stretch(maps[1])};
    const std::size_t tried = maps[0].cut.tried + maps[1].cut.tried;
    const double seconds = maps[0].cut_seconds + maps[1].cut_seconds;
    CutMap& kept = maps[image_rms[1] < image_rms[0] ? 1 : 0];
    kept.graph_image_rms = std::move(image_rms);
    kept.cut.graph_l2_stretch = std::move(graph_stretch);
    kept.cut.tried = tried;
    kept.cut_seconds = seconds;
    return std::move(kept);
}

}  // namespace gimg::passes
