// Step 5 of repair_mesh (repair.h): faces of zero area removed by OpenMesh's flips and collapses,
// which keep a manifold mesh manifold (is_flip_ok, is_collapse_ok: the link condition).
#include "repair_parts.h"

#include "gimg/geometry/topology.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <stdexcept>

namespace gimg::geo::detail {

namespace {

struct Traits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    VertexAttributes(OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
using Handle = OpenMesh::SmartFaceHandle;

// A needle's short edge is at most this fraction of its longest; a cap has its corner farther
// from both ends.
constexpr double kNeedle = 1e-6;
// Each pass visits every face once; flips can make new faces of zero area where three or more
// corners are collinear, so passes repeat while they change something, at most this many times.
constexpr int kMaxPasses = 64;

glm::dvec3 position(const TriMesh& m, OpenMesh::VertexHandle v) {
    const OpenMesh::Vec3d& p = m.point(v);
    return {p[0], p[1], p[2]};
}

bool zero_area(const TriMesh& m, Handle f) {
    const auto h = f.halfedge();
    return zero_area_triangle(position(m, h.from()), position(m, h.to()), position(m, h.next().to()));
}

// Removes one face of zero area, or returns false where no allowed change does.
bool remove_one(TriMesh& m, Handle f, RepairReport& report) {
    OpenMesh::SmartHalfedgeHandle longest, shortest;
    double longest_length = -1.0, shortest_length = 0.0;
    for (auto h : f.halfedges()) {
        const double length = (m.point(h.to()) - m.point(h.from())).norm();
        if (length > longest_length) longest_length = length, longest = h;
        if (!shortest.is_valid() || length < shortest_length) shortest_length = length, shortest = h;
    }
    auto collapse = [&](OpenMesh::SmartHalfedgeHandle h) {
        for (auto way : {h, h.opp()})
            if (m.is_collapse_ok(way)) {
                m.collapse(way);
                ++report.collapsed_edges;
                return true;
            }
        return false;
    };
    if (shortest_length <= kNeedle * longest_length) return collapse(shortest);
    const auto edge = longest.edge();
    if (edge.is_boundary()) {
        // Dropping the cap leaves its corner on the boundary; where the corner is there already
        // through another gap, it would become a vertex of two fans.
        const auto corner = longest.next().to();
        const bool corner_on_side = longest.next().opp().is_boundary() || longest.prev().opp().is_boundary();
        if (corner.is_boundary() && !corner_on_side) return false;
        m.delete_face(f, true);
        return true;
    }
    if (m.is_flip_ok(edge)) {
        m.flip(edge);
        ++report.flipped_edges;
        return true;
    }
    return collapse(shortest);
}

}  // namespace

void remove_zero_area_faces(Mesh& mesh, RepairReport& report) {
    for (const glm::uvec3& t : mesh.triangles) report.zero_area_faces += zero_area_face(mesh, t) ? 1 : 0;
    if (report.zero_area_faces == 0) return;
    TriMesh m;
    OpenMesh::VPropHandleT<std::uint32_t> origin_handle;
    m.add_property(origin_handle);
    auto origin = [&](OpenMesh::VertexHandle v) -> std::uint32_t& { return m.property(origin_handle, v); };
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        origin(m.add_vertex({p.x, p.y, p.z})) = v;
    }
    for (const glm::uvec3& t : mesh.triangles)
        if (!m.add_face(m.vertex_handle(t.x), m.vertex_handle(t.y), m.vertex_handle(t.z)).is_valid())
            throw std::logic_error("repair: a face the manifold, oriented mesh could not take");
    for (int pass = 0; pass < kMaxPasses; ++pass) {
        bool changed = false;
        for (std::size_t i = 0; i < m.n_faces(); ++i) {
            const Handle f = OpenMesh::make_smart(m.face_handle(int(i)), m);
            if (m.status(f).deleted() || !zero_area(m, f)) continue;
            changed = remove_one(m, f, report) || changed;
        }
        if (!changed) break;
    }
    m.garbage_collection();
    Mesh out;
    for (auto v : m.vertices()) {
        out.positions.push_back(position(m, v));
        if (mesh.has_texcoords()) out.texcoords.push_back(mesh.texcoords[origin(v)]);
        if (mesh.has_normals()) out.normals.push_back(mesh.normals[origin(v)]);
    }
    for (auto f : m.faces()) {
        glm::uvec3 t;
        int k = 0;
        for (auto v : f.vertices()) t[k++] = std::uint32_t(v.idx());
        out.triangles.push_back(t);
        report.zero_area_left += zero_area_face(out, t) ? 1 : 0;
    }
    mesh = std::move(out);
}

}  // namespace gimg::geo::detail
