// A surface cut open into a disk for the square map: the initial cut (or a seam), then paths toward
// the stretch of Floater's map, as Gu, Gortler and Hoppe (2002) augment theirs.
#include "gimg/geometry/disk_cut.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/parameterize.h"
#include "parameterize/reweighting.h"

#include <glm/geometric.hpp>

namespace gimg::passes {

namespace {

struct Opened {
    geo::OpenedMesh mesh;
    std::size_t split_edges = 0;
    std::vector<glm::dvec2> uv;  // Floater's map
    std::size_t flipped = 0;     // its triangles turned over: regions crushed below rounding
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
    o.split_edges = geo::split_dividing_edges(o.mesh);
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

}  // namespace

DiskCut cut_to_disk(Context* ctx, const geo::Mesh& mesh, const DiskCutOptions& options) {
    check_cuttable_mesh(mesh);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    std::vector<std::uint8_t> cut = geo::initial_cut(mesh, adj);
    const auto on_cut = [&](const std::vector<std::uint8_t>& c) {
        for (std::size_t e = 0; e < c.size(); ++e)
            if (c[e] || adj.edge_face_count(e) == 1) return true;
        return false;
    };
    // A closed genus-0 surface: the tree of faces crosses every edge it leaves.
    if (!on_cut(cut)) geo::add_seam(mesh, adj, cut);

    // Every path is tried; the cut kept is the one of the first k paths whose map is best.
    Opened last = open_and_map(ctx, mesh, adj, cut);
    Opened best = last;
    std::vector<std::uint8_t> best_cut = cut;
    DiskCut out;
    out.l2_stretch.push_back(last.l2_stretch);
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
        last = open_and_map(ctx, mesh, adj, cut);
        out.l2_stretch.push_back(last.l2_stretch);
        if (better(last, best, options.stop_fall)) {
            best = last;
            best_cut = cut;
            out.paths = k;
        }
    }
    cut = std::move(best_cut);
    if (best.flipped)
        throw geo::InputError("cutting the mesh open: the best of " + std::to_string(out.l2_stretch.size()) +
                              " cuts tried still turns " + std::to_string(best.flipped) +
                              " triangles over in Floater's map (parts crushed below rounding, which more "
                              "--cut-paths can free, or closed in by the cut against one side of the square)");
    out.disk = std::move(best.mesh.disk);
    out.source = std::move(best.mesh.source);
    out.split_edges = best.split_edges;
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

}  // namespace gimg::passes
