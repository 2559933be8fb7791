// The multigrid smoother's constants (passes/solvers/multigrid.h, ChebyshevSmoother), rounded
// to float, and the level's rows, as the smoothing passes' push constants. `write_terms`: the pass
// writes row i's term of r . z (the finest level's last pass only).
layout(push_constant) uniform Push {
    uint rows;
    uint write_terms;
    float theta_inverse;
    float c0;
    float c1;
    float k;
};
