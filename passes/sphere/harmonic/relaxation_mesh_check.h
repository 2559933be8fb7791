#pragma once
// The sphere input check from a laid-out level (relaxation_mesh.h), for the gpu method's direct
// route, which lays the level out anyway. build_relaxation_mesh walks every vertex's fan and throws
// unless the triangles around each vertex form one closed cycle in which every spoke is entered
// once and left once: so a level that exists proves its mesh closed, edge- and vertex-manifold,
// consistently oriented and free of isolated vertices. What is left of check_sphere_input is
// cheap: no collapsed or zero-area face, one component, Euler characteristic 2, and at least 4
// faces (the 2-face "pillow" of one triangle twice is the only closed fan layout with a duplicate
// face). This takes 2.7 ms on armadillo_loop1 and 0.8 on armadillo, where check_sphere_input takes
// 66-73 and 19 ms; run on a second thread beside the level's layout and the start's setup it
// shared the two cores with them, and the whole map took 4% longer (medians of 11, 4 rounds).
#include "sphere/harmonic/relaxation_mesh.h"

#include "gimg/geometry/mesh.h"

namespace gimg::passes::detail {

// True when `mesh`, whose level is `level`, would pass check_sphere_input. False means: ask
// check_sphere_input, which says what is wrong.
bool relaxation_mesh_is_sphere(const geo::Mesh& mesh, const RelaxationMesh& level);

}  // namespace gimg::passes::detail
