// BiCGSTAB's scalars for a pair of right-hand sides (passes/solvers/bicgstab.cpp, BicgScalars).
struct BicgScalars {
    dvec2 rho, alpha, omega, beta;
};
