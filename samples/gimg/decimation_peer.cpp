// OpenMesh's quadric decimation (decimation_peer.h).
#include "decimation_peer.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <vector>

namespace gimg::cli {

geo::Mesh quadric_decimation(const geo::Mesh& mesh, std::size_t vertices) {
    struct Traits : OpenMesh::DefaultTraits {
        using Point = OpenMesh::Vec3d;
    };
    using TriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
    TriMesh m;
    std::vector<TriMesh::VertexHandle> v;
    for (const glm::dvec3& p : mesh.positions) v.push_back(m.add_vertex({p.x, p.y, p.z}));
    for (const glm::uvec3& t : mesh.triangles) m.add_face(v[t[0]], v[t[1]], v[t[2]]);
    OpenMesh::Decimater::DecimaterT<TriMesh> decimater(m);
    OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.initialize();
    decimater.decimate_to(vertices);
    m.garbage_collection();
    geo::Mesh out;
    for (auto vh : m.vertices()) {
        const auto p = m.point(vh);
        out.positions.push_back({p[0], p[1], p[2]});
    }
    for (auto fh : m.faces()) {
        auto it = m.cfv_iter(fh);
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k, ++it) t[k] = std::uint32_t(it->idx());
        out.triangles.push_back(t);
    }
    return out;
}

}  // namespace gimg::cli
