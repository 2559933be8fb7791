#include "cgal_peer.h"

#if GIMG_HAS_CGAL
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Error_code.h>
#include <CGAL/Surface_mesh_parameterization/Iterative_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Square_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <optional>
#include <unordered_set>
#include <utility>
#endif

namespace gimg::cli {

const char* cgal_square_map_name(CgalSquareMap method) {
    switch (method) {
        case CgalSquareMap::MeanValue:
            return "cgal-mean-value";
        case CgalSquareMap::DiscreteAuthalic:
            return "cgal-discrete-authalic";
        case CgalSquareMap::DiscreteConformal:
            return "cgal-discrete-conformal";
        case CgalSquareMap::IterativeAuthalic:
            return "cgal-iterative-authalic";
    }
    return "cgal-unknown";
}

#if GIMG_HAS_CGAL

bool cgal_available() { return true; }

namespace {
namespace SMP = CGAL::Surface_mesh_parameterization;
using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Vertex = SurfaceMesh::Vertex_index;
using Border = SMP::Square_border_arc_length_parameterizer_3<SurfaceMesh>;

// CGAL's own get_error_message() skips ERROR_NO_TOPOLOGICAL_BALL, so its texts are off by one from there on.
std::string error_text(SMP::Error_code code) {
    static const char* const texts[] = {"success",
                                        "input mesh is empty",
                                        "input mesh is not triangular",
                                        "input mesh is not a topological disc",
                                        "input mesh is not a topological ball",
                                        "the border is too short for this border parameterization",
                                        "this parameterization method requires a convex border",
                                        "cannot solve the linear system",
                                        "no one-to-one mapping",
                                        "a method received an unexpected parameter"};
    const auto i = std::size_t(code);
    return std::string("CGAL: ") + (i < std::size(texts) ? texts[i] : "unknown error");
}

// CGAL 5.5's Iterative_authalic_parameterizer_3 hard-codes DEBUG_L0 on: each iteration prints to
// std::cout and writes "last_solve.off" into the working directory. Mute std::cout and run it from
// a scratch directory where that name is a directory, so the write fails at once.
class QuietIterativeAuthalic {
public:
    QuietIterativeAuthalic() : cout_(std::cout.rdbuf(nullptr)) {
        namespace fs = std::filesystem;
        std::error_code ec;
        std::string dir = (fs::temp_directory_path(ec) / "gimg-cgal-XXXXXX").string();
        if (ec || !mkdtemp(dir.data())) return;
        scratch_ = dir;
        fs::create_directory(scratch_ / "last_solve.off", ec);
        previous_ = fs::current_path(ec);
        if (!ec) fs::current_path(scratch_, ec);
        if (ec) previous_.clear();
    }
    ~QuietIterativeAuthalic() {
        std::error_code ec;
        if (!previous_.empty()) std::filesystem::current_path(previous_, ec);
        if (!scratch_.empty()) std::filesystem::remove_all(scratch_, ec);
        std::cout.rdbuf(cout_);
    }
    QuietIterativeAuthalic(const QuietIterativeAuthalic&) = delete;
    QuietIterativeAuthalic& operator=(const QuietIterativeAuthalic&) = delete;

private:
    std::streambuf* cout_;
    std::filesystem::path scratch_, previous_;
};

CgalSquareMapResult square_map(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners, CgalSquareMap method,
                               unsigned iterations) {
    CgalSquareMapResult result;
    const std::size_t n = mesh.positions.size();
    for (std::size_t k = 0; k < 4; ++k) {
        if (corners[k] >= n) return {{}, 0.0, "corner " + std::to_string(k) + " is not a vertex of the mesh"};
        for (std::size_t j = 0; j < k; ++j)
            if (corners[j] == corners[k]) return {{}, 0.0, "the four corners must be distinct vertices"};
    }
    if (method == CgalSquareMap::IterativeAuthalic && iterations == 0)
        return {{}, 0.0, "the iterative authalic map needs at least one iteration"};

    // Same vertex indices as gimg's mesh: Surface_mesh numbers vertices in the order they are added.
    SurfaceMesh sm;
    sm.reserve(SurfaceMesh::size_type(n), SurfaceMesh::size_type(3 * mesh.triangles.size() / 2 + n),
               SurfaceMesh::size_type(mesh.triangles.size()));
    for (const glm::dvec3& p : mesh.positions) sm.add_vertex(Kernel::Point_3(p.x, p.y, p.z));
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        if (sm.add_face(Vertex(t.x), Vertex(t.y), Vertex(t.z)) == SurfaceMesh::null_face())
            return {{}, 0.0, "CGAL's Surface_mesh refused triangle " + std::to_string(f) + " (not manifold)"};
    }

    // The border halfedge leaving corner 0, and the loop it runs along, which must hold the others.
    const Vertex corner0(corners[0]);
    SurfaceMesh::Halfedge_index bhd = SurfaceMesh::null_halfedge();
    for (const auto h : sm.halfedges())
        if (sm.is_border(h) && sm.source(h) == corner0) bhd = h;
    if (bhd == SurfaceMesh::null_halfedge()) return {{}, 0.0, "corner 0 is not on the mesh's border"};
    std::unordered_set<std::uint32_t> loop;
    for (const auto v : CGAL::vertices_around_face(bhd, sm)) loop.insert(std::uint32_t(v));
    for (std::size_t k = 1; k < 4; ++k)
        if (!loop.count(corners[k]))
            return {{}, 0.0, "corner " + std::to_string(k) + " is not on corner 0's border loop"};

    auto uvmap = sm.add_property_map<Vertex, Kernel::Point_2>("v:uv", Kernel::Point_2(0.0, 0.0)).first;
    const Border border(corner0, Vertex(corners[1]), Vertex(corners[2]), Vertex(corners[3]));
    std::optional<QuietIterativeAuthalic> quiet;
    if (method == CgalSquareMap::IterativeAuthalic) quiet.emplace();

    using Clock = std::chrono::steady_clock;
    SMP::Error_code code = SMP::OK;
    const auto start = Clock::now();
    switch (method) {
        case CgalSquareMap::MeanValue:
            code = SMP::parameterize(sm, SMP::Mean_value_coordinates_parameterizer_3<SurfaceMesh, Border>(border), bhd,
                                     uvmap);
            break;
        case CgalSquareMap::DiscreteAuthalic:
            code =
                SMP::parameterize(sm, SMP::Discrete_authalic_parameterizer_3<SurfaceMesh, Border>(border), bhd, uvmap);
            break;
        case CgalSquareMap::DiscreteConformal:
            code = SMP::parameterize(sm, SMP::Discrete_conformal_map_parameterizer_3<SurfaceMesh, Border>(border), bhd,
                                     uvmap);
            break;
        case CgalSquareMap::IterativeAuthalic: {
            SMP::Iterative_authalic_parameterizer_3<SurfaceMesh, Border> parameterizer(border);
            code = parameterizer.parameterize(sm, bhd, uvmap, iterations);
            break;
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    quiet.reset();
    if (code != SMP::OK) return {{}, result.seconds, error_text(code)};

    result.uv.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Kernel::Point_2& p = uvmap[Vertex(SurfaceMesh::size_type(i))];
        result.uv[i] = {p.x(), p.y()};
    }
    // CGAL sends the first corner met along the border halfedges (which run against the mesh's
    // orientation) to (0,0) and the next ones around the square; find the square's symmetry that
    // puts corner k where the API promises and apply it to every uv.
    const glm::dvec2 wanted[4] = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
    for (int s = 0; s < 8; ++s) {
        const auto symmetry = [s](glm::dvec2 p) {
            if (s & 4) std::swap(p.x, p.y);
            if (s & 1) p.x = 1.0 - p.x;
            if (s & 2) p.y = 1.0 - p.y;
            return p;
        };
        bool fits = true;
        for (std::size_t k = 0; k < 4; ++k) {
            const glm::dvec2 d = symmetry(result.uv[corners[k]]) - wanted[k];
            fits = fits && std::abs(d.x) < 1e-9 && std::abs(d.y) < 1e-9;
        }
        if (!fits) continue;
        for (glm::dvec2& p : result.uv) p = symmetry(p);
        return result;
    }
    return {{}, result.seconds, "the corners are not in order along the border"};
}
}  // namespace

CgalSquareMapResult cgal_square_map(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners,
                                    CgalSquareMap method, unsigned iterations) {
    try {
        return square_map(mesh, corners, method, iterations);
    } catch (const std::exception& e) {
        return {{}, 0.0, std::string("CGAL: ") + e.what()};
    } catch (...) {
        return {{}, 0.0, "CGAL: unknown exception"};
    }
}

#else

bool cgal_available() { return false; }
CgalSquareMapResult cgal_square_map(const geo::Mesh&, const std::array<std::uint32_t, 4>&, CgalSquareMap, unsigned) {
    return {{}, 0.0, "built without CGAL"};
}

#endif

}  // namespace gimg::cli
