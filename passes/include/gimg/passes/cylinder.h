#pragma once
// Cylindrical geometry images (seed 003, chapters 2 and 4). Every method gives pixel (u, v) one
// meaning: the line perpendicular to the cylinder's axis (the y axis) at height
// y_v = 1 - (v + 0.5) / H in direction theta_u = 2 pi (u + 0.5) / W, walked from the wall (t = 1)
// through the axis to the opposite wall (t = -1), keeps the largest t at which it crosses a
// triangle facing the wall it starts from (normal . (cos theta_u, 0, sin theta_u) > 0). t > 0 is
// the paper's front projection, t < 0 its back projection; no crossing leaves the pixel empty.
//
// All methods read the same float32 geometry (positions already in the cylinder frame, plus an
// optional per-image 3x4 transform applied in double), so they can agree to rounding.

#include "gimg/engine/context.h"
#include "gimg/engine/plan.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace gimg::passes {

struct CylinderImage {
    std::uint32_t width = 0, height = 0;
    std::vector<float> distance;     // row-major from the top row; meaningful where covered
    std::vector<std::uint8_t> covered;  // 1 where a surface was hit
    CylinderImage() = default;
    CylinderImage(std::uint32_t w, std::uint32_t h)
        : width(w), height(h), distance(std::size_t(w) * h, 0.0f), covered(std::size_t(w) * h, 0) {}
    std::size_t index(std::uint32_t u, std::uint32_t v) const { return std::size_t(v) * width + u; }
};

// Triangles in (or, with a transform, mapped into) the cylinder frame.
struct CylinderMesh {
    std::vector<float> positions;       // x, y, z per vertex
    std::vector<std::uint32_t> triangles;  // three vertex indices per face
    std::size_t face_count() const { return triangles.size() / 3; }
};

// Row-major 3x4: p_cylinder = M * (p, 1). The identity means "already in the frame".
using CylinderTransform = std::array<float, 12>;
inline constexpr CylinderTransform kIdentityTransform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

// The directions of the W pixel columns, (cos theta_u, sin theta_u) in double: every method uses
// this same table, as the paper tabulates it.
std::vector<std::array<double, 2>> cylinder_directions(std::uint32_t width);

// The CPU reference: a ray per pixel through a BVH, multithreaded.
CylinderImage cylinder_raycast(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                               const CylinderTransform& transform = kIdentityTransform);

// The paper's own CPU algorithm (seed 003, ch. 4, the cylindrical Z-buffer): triangles are
// classified front / back / exception, scan-converted row by row along their curved edges, and
// each covered pixel's d comes from a 2D line intersection in the scan plane. The same image as
// cylinder_raycast to rounding. Large meshes are split over threads by bands of rows; the image
// does not depend on the thread count.
CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform = kIdentityTransform);
// The same with a given number of threads (1: the paper's single-threaded algorithm; 0: choose).
CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform, unsigned threads);

// The GPU cylindrical Z-buffer. Meshes are uploaded once; project() renders any number of images
// (mesh, transform) in one graph execution, tiled into one atlas.
class CylinderZBuffer {
public:
    CylinderZBuffer(Context& ctx, std::uint32_t width, std::uint32_t height);
    ~CylinderZBuffer();
    CylinderZBuffer(const CylinderZBuffer&) = delete;
    CylinderZBuffer& operator=(const CylinderZBuffer&) = delete;

    // Uploads a mesh; returns its id for project().
    std::uint32_t add_mesh(const CylinderMesh& mesh);

    struct Job {
        std::uint32_t mesh = 0;
        CylinderTransform transform = kIdentityTransform;
    };
    std::vector<CylinderImage> project(std::span<const Job> jobs);
    CylinderImage project(std::uint32_t mesh, const CylinderTransform& transform = kIdentityTransform);

    // GPU time of the last project() (sum of its passes), and the plan behind it.
    double last_gpu_ms() const { return last_gpu_ms_; }
    bool double_precision() const;

private:
    struct State;
    std::unique_ptr<State> state_;
    double last_gpu_ms_ = 0.0;
};

}  // namespace gimg::passes
