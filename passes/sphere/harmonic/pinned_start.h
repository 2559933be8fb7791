#pragma once
// The start of the gpu method's direct route: the first step of Choi, Lam and Lui's map (the
// `linear` method), solved by the planar polish's multigrid conjugate gradients on the GPU instead
// of a sparse direct solver. The mesh minus its most regular triangle is mapped into the plane by
// the cotangent harmonic map that pins that triangle's corners to a flat copy of it, and the plane
// goes onto the sphere by the balanced inverse stereographic projection. The map is accurate far
// from the pinned triangle, around the south pole: that is where the polish pins its cap
// (sphere_harmonic.cpp), and it recomputes everything else. No hierarchy is needed on this route.
#include "sphere/harmonic/chart_problem.h"
#include "sphere/harmonic/relaxation_mesh.h"

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"

#include <functional>
#include <string>
#include <vector>

namespace gimg::passes::detail {

struct PinnedStart {
    std::string why;                           // empty when the map is usable
    std::vector<glm::dvec3> y;                 // per mesh vertex, on the unit sphere
    glm::dvec3 accurate_pole{0.0, 0.0, -1.0};  // centroid direction of the face nearest the plane's origin
    std::size_t free_vertices = 0;
    std::size_t iterations = 0;  // conjugate gradient iterations
    double residual = 0.0;
    double gpu_ms = 0.0;
};

// `level` must be build_relaxation_mesh(mesh) (the same vertex ids). `tolerance`: the conjugate
// gradients' relative residual. `before_gpu` (may be empty) is called once the CPU setup (the
// problem and its multigrid hierarchy) is done, before the first GPU work; it is not called when
// the setup already says why the start cannot be made.
PinnedStart pinned_start_gpu(Context& ctx, const geo::Mesh& mesh, const RelaxationMesh& level, double tolerance,
                             bool timestamps, const std::function<void(std::size_t, double)>& progress = {},
                             const std::function<void()>& before_gpu = {});

// Sum of the signed solid angles of the triangles of `y`: 4 pi for a map that covers the sphere
// once; a multiple of it for one that wraps around more than once with no triangle flipped.
double total_solid_angle(const RelaxationMesh& level, const std::vector<glm::dvec3>& y);

}  // namespace gimg::passes::detail
