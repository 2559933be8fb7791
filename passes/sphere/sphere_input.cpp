// What a spherical parameterization needs of its input, said plainly when it is missing.
#include "gimg/passes/sphere.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"

#include <cstdio>

namespace gimg::passes {

namespace {

std::string at(const glm::dvec3& p) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", p.x, p.y, p.z);
    return buf;
}

std::string plural(std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

void check_sphere_input(const geo::Mesh& mesh) {
    const std::string need = ": spherical parameterization needs ";
    if (mesh.face_count() == 0) throw geo::InputError("the mesh has no faces" + need + "a closed surface");
    const geo::MeshInfo info = geo::analyze_topology(mesh);
    if (info.nonfinite_vertices)
        throw geo::InputError(plural(info.nonfinite_vertices, "vertex has", "vertices have") +
                              " NaN or infinite coordinates");
    if (info.components > 1)
        throw geo::InputError(std::to_string(info.components) + " separate pieces" + need +
                              "one (gimg repair --largest keeps the largest)");
    if (info.non_manifold_edges) {
        const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
        for (std::size_t e = 0; e < adj.edge_count(); ++e)
            if (adj.edge_face_count(e) > 2)
                throw geo::InputError(
                    "non-manifold edge at " +
                    at(0.5 * (mesh.positions[adj.edges[2 * e]] + mesh.positions[adj.edges[2 * e + 1]])) + " (" +
                    plural(info.non_manifold_edges, "such edge", "such edges") + ")" + need +
                    "a manifold surface (gimg repair opens them)");
    }
    if (info.non_manifold_vertices)
        throw geo::InputError(plural(info.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") +
                              " (faces meeting at a point only)" + need +
                              "a manifold surface (gimg repair opens them)");
    if (info.boundary_loops)
        throw geo::InputError(plural(info.boundary_loops, "boundary loop", "boundary loops") + need +
                              "a closed surface");
    if (!info.component_info.empty() && info.component_info.front().genus.value_or(0) != 0)
        throw geo::InputError("genus " + std::to_string(*info.component_info.front().genus) + need + "genus 0");
    if (!info.oriented)
        throw geo::InputError("faces are not consistently oriented (" +
                              plural(info.inconsistent_edges, "edge disagrees", "edges disagree") + ")" + need +
                              "one orientation (gimg repair turns them)");
    if (info.degenerate_faces)
        throw geo::InputError(plural(info.degenerate_faces, "degenerate face", "degenerate faces") +
                              " (zero area or a repeated vertex)" + need +
                              "proper triangles (gimg repair removes them)");
    if (info.duplicate_faces)
        throw geo::InputError(plural(info.duplicate_faces, "duplicate face", "duplicate faces") + need +
                              "a simple surface (gimg repair removes them)");
    if (info.isolated_vertices)
        throw geo::InputError(plural(info.isolated_vertices, "vertex belongs", "vertices belong") + " to no face" +
                              need + "every vertex on the surface (gimg repair removes the others)");
}

}  // namespace gimg::passes
