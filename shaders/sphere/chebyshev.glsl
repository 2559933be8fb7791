// The multigrid smoother's constants (passes/sphere/plane_multigrid.h, ChebyshevSmoother) and the
// level's rows, as the smoothing passes' push constants. `write_terms`: the pass writes row i's
// term of r . z (the finest level's last pass only).
layout(push_constant) uniform Push {
    uint rows;
    uint write_terms;
    double theta_inverse;
    double c0;
    double c1;
    double k;
};
