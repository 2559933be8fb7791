#pragma once
// The multigrid V-cycle (multigrid.h) on the render graph, in float32: the hierarchy is uploaded
// once (GpuVcycle) and its passes are recorded into a graph as often as a solver applies it
// (VcycleRecorder). Conjugate gradients apply it once an iteration, BiCGSTAB twice. The CPU twin
// is apply_multigrid_cpu(..., CyclePrecision::float32).
#include "solvers/matrix_texels.h"
#include "solvers/multigrid.h"

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"

#include <string>
#include <vector>

namespace gimg::passes::detail {

class GpuVcycle {
public:
    // `name` prefixes the images and passes ("plane mg", "bicgstab mg").
    GpuVcycle(Context& ctx, const Multigrid& mg, const std::string& name);
    bool has_levels() const { return !levels_.empty(); }

private:
    friend class VcycleRecorder;
    // A smoothed level, its entries in float (the cycle's type).
    struct Level {
        TexelMatrix a, prolong, restrict_;  // a's rows carry 1 / a_ii
        Image ad_entries;                   // A's entries divided by their column's diagonal, for the presmoothing
        ChebyshevSmoother smoother;
    };
    std::string name_;
    std::vector<Level> levels_;
    Image coarsest_inverse_;  // row-major, one double a texel
    std::uint32_t coarsest_rows_ = 0;
};

// A GpuVcycle imported into one graph, with the cycle's vectors.
class VcycleRecorder {
public:
    VcycleRecorder(Graph& g, GpuVcycle& cycle);
    // z = V-cycle(b); b and z are float vectors (float_vector_desc) of the finest level's rows. With
    // write_terms its last pass writes row i's b . z into terms[i] (a double); else terms is bound
    // and left alone.
    void add(ImageHandle b, ImageHandle& z, BufferHandle& terms, bool write_terms, const std::string& suffix);
    // The finest level's rows image (1 / a_ii in each row's texel); only when cycle.has_levels().
    ImageHandle finest_rows() const { return levels_.front().a.rows; }

private:
    struct MatrixHandles {
        ImageHandle rows, entries;
        std::uint32_t count;
    };
    struct LevelHandles {
        MatrixHandles a, prolong, restrict_;
        ImageHandle ad_entries, b, mix, x, r, x1, out;
        ChebyshevSmoother smoother;
    };
    Graph& g_;
    std::string name_;
    std::vector<LevelHandles> levels_;
    ImageHandle coarsest_inverse_, coarsest_b_, coarsest_x_;
    std::uint32_t coarsest_rows_ = 0;
};

}  // namespace gimg::passes::detail
