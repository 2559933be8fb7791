#pragma once
// Cylindrical geometry images (the cylindrical-projection thesis, chapters 2 and 4; docs/cylinder.md). Every method gives pixel (u, v) one
// meaning: the line perpendicular to the cylinder's axis (the y axis) at height
// y_v = 1 - (v + 0.5) / H in direction theta_u = 2 pi (u + 0.5) / W, walked from the wall (t = 1)
// through the axis to the opposite wall (t = -1), keeps the largest t at which it crosses a
// triangle facing the wall it starts from (normal . (cos theta_u, 0, sin theta_u) > 0). t > 0 is
// the paper's front projection, t < 0 its back projection; no crossing leaves the pixel empty.
//
// All methods read the same float32 geometry (positions already in the cylinder frame, plus an
// optional per-image 3x4 transform applied in double), so they can agree to rounding.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/engine/plan.h"
#include "gimg/geometry/image.h"
#include "gimg/geometry/mesh.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <memory>
#include <span>
#include <vector>

namespace gimg::geo {
class TriangleBvh;
}  // namespace gimg::geo

namespace gimg::passes {

struct CylinderImage {
    std::uint32_t width = 0, height = 0;
    std::vector<float> distance;        // row-major from the top row; meaningful where covered
    std::vector<std::uint8_t> covered;  // 1 where a surface was hit
    CylinderImage() = default;
    CylinderImage(std::uint32_t w, std::uint32_t h)
        : width(w), height(h), distance(std::size_t(w) * h, 0.0f), covered(std::size_t(w) * h, 0) {}
    std::size_t index(std::uint32_t u, std::uint32_t v) const { return std::size_t(v) * width + u; }
};

// Triangles in (or, with a transform, mapped into) the cylinder frame.
struct CylinderMesh {
    std::vector<float> positions;          // x, y, z per vertex
    std::vector<std::uint32_t> triangles;  // three vertex indices per face
    std::size_t face_count() const { return triangles.size() / 3; }
};

// Row-major 3x4: p_cylinder = M * (p, 1). The identity means "already in the frame".
using CylinderTransform = std::array<float, 12>;
inline constexpr CylinderTransform kIdentityTransform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
// The top three rows of an affine glm matrix (column-major) as a CylinderTransform.
CylinderTransform to_cylinder_transform(const glm::dmat4& affine);

// Where the cylinder frame sits in the model's: p_cylinder = scale * (rotation * p) + translation.
// rotation comes from PCA (main axis -> y, never a mirror); scale and translation fit the model
// into the cylinder of radius 1 and height 1 (y from 0 to 1), centred on the axis and in height,
// with a 0.1 % margin so no point lies exactly on the wall.
struct CylinderFrame {
    glm::dmat3 rotation{1.0};
    glm::dvec3 translation{0.0};
    double scale = 1.0;
    glm::dvec3 to_cylinder(const glm::dvec3& p) const { return scale * (rotation * p) + translation; }
    glm::dvec3 to_model(const glm::dvec3& q) const;
};

// align = false keeps the model's orientation (y stays up) and only centres and scales it.
CylinderFrame fit_cylinder_frame(const geo::Mesh& mesh, bool align = true);
// The mesh's positions mapped into the frame in double, then stored as float32.
CylinderMesh make_cylinder_mesh(const geo::Mesh& mesh, const CylinderFrame& frame);

// --auto image size as the paper chooses it: W = 2H with 2 W H close to the face count.
std::array<std::uint32_t, 2> auto_cylinder_size(std::size_t faces);

// The picture people look at: brightness = |d| (relative to the image's largest |d|), warm for
// d > 0 (seen directly), cold for d < 0 (seen through the axis), black where empty.
geo::RgbaImage cylinder_preview(const CylinderImage& image);

// DIR/distance.exr (float32 channels "d" and "mask": 1 covered, 0 empty), DIR/distance.png (the
// preview) and DIR/frame.json (rotation, translation, scale, image layout), each written
// atomically; DIR is created if missing.
struct CylinderFileInfo {
    std::string source;  // the mesh the image came from
    std::string method;  // zbuffer, raycast or scanline
};
void write_cylinder_files(const std::filesystem::path& dir, const CylinderImage& image, const CylinderFrame& frame,
                          const CylinderFileInfo& info);
// The three appear together (geo::OutputSet), and frame.json records the image's size and a stamp of
// its contents.
// Reading them back (reconstruction). Throws geo::InputError for missing or malformed files: no
// "mask" channel or one not 0 or 1, d outside [-1, 1], a rotation that is not one, non-finite
// values.
CylinderImage read_cylinder_exr(const std::filesystem::path& path);
CylinderFrame read_cylinder_frame(const std::filesystem::path& path);
// An image with the frame.json beside it, checked to belong together (size and stamp).
struct CylinderFiles {
    CylinderImage image;
    CylinderFrame frame;
};
CylinderFiles read_cylinder_files(const std::filesystem::path& exr_path);

// The directions of the W pixel columns, (cos theta_u, sin theta_u) in double: every method uses
// this same table, as the paper tabulates it.
std::vector<std::array<double, 2>> cylinder_directions(std::uint32_t width);

// The mesh with the transform applied in double (what every method intersects).
geo::Mesh to_cylinder_frame(const CylinderMesh& mesh, const CylinderTransform& transform = kIdentityTransform);

// The CPU reference: a ray per pixel through a BVH, multithreaded.
CylinderImage cylinder_raycast(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                               const CylinderTransform& transform = kIdentityTransform);

// The same rays on the GPU (GpuRayCaster, gimg/passes/raycast.h): the same image bit for bit.
// Needs shaderFloat64.
CylinderImage cylinder_raycast_gpu(Context& ctx, const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                   const CylinderTransform& transform = kIdentityTransform);
// The same through a caster already built over to_cylinder_frame(mesh, transform), which a caller
// casting more rays at the same mesh keeps (the hierarchy's GPU encoder).
class GpuRayCaster;
CylinderImage cylinder_raycast_gpu(GpuRayCaster& caster, std::uint32_t width, std::uint32_t height);

// The same with the BVH built once and reused (benchmarks time the two apart).
class CylinderRaycaster {
public:
    explicit CylinderRaycaster(const CylinderMesh& mesh, const CylinderTransform& transform = kIdentityTransform);
    ~CylinderRaycaster();
    CylinderImage project(std::uint32_t width, std::uint32_t height) const;
    // The BVH over to_cylinder_frame(mesh, transform), for callers casting more rays at the mesh.
    const geo::TriangleBvh& bvh() const;

private:
    struct Bvh;
    std::unique_ptr<Bvh> bvh_;
};

// The paper's own CPU algorithm (the cylindrical-projection thesis, ch. 4, the cylindrical Z-buffer): triangles are
// classified front / back / exception, scan-converted row by row along their curved edges, and
// each covered pixel's d comes from a 2D line intersection in the scan plane. The same image as
// cylinder_raycast to rounding. Large meshes are split over threads by bands of rows; the image
// does not depend on the thread count.
CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform = kIdentityTransform);
// The same with a given number of threads (1: the paper's single-threaded algorithm; 0: choose).
CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform, unsigned threads);

// Where the Z-buffer decides pieces larger than small_pixels pixels.
enum class CylinderLargePieces {
    Auto,      // Compute on CPU devices (lavapipe), Graphics on GPUs
    Graphics,  // the graphics pipeline's curved raster: fragment stage and depth test
    Compute,   // a compute pass, one workgroup a piece sharing out its pixels
};

struct CylinderZBufferOptions {
    // Pieces whose pixel rectangle holds at most this many pixels are decided by the classify
    // compute pass itself (the fragment stage's exact test, atomicMax per pixel); larger ones go
    // to the large-piece pass. Every split gives the same image; it is a speed choice: 0 sends
    // every piece to the large-piece pass, UINT32_MAX none.
    std::uint32_t small_pixels = 64;
    // The large-piece pass. lavapipe rasterises on the CPU, setting up each primitive on one thread:
    // bunny at 540x270 (222 large pieces) took 5.0-5.2 ms an image through its graphics pipeline,
    // 4.5-4.7 ms with the compute pass.
    CylinderLargePieces large_pieces = CylinderLargePieces::Auto;
    // The exact test in double precision where the device has shaderFloat64 (the ray caster's
    // arithmetic); false runs the float32 path that devices without it get.
    bool double_precision = true;
    // GPU time of every pass from timestamps (last_gpu_ms, last_pass_timings). Off by default: on
    // lavapipe the timestamps cost 0.2-0.5 ms of a 5 ms projection (armadillo at 540x270); on GPUs
    // they cost next to nothing.
    bool timestamps = false;
};

class CylinderZBuffer;

// What add_cylinder leaves in a graph: `count` images of width x height, one after another, each
// row-major from the top row, as float32 d with NaN where no surface was hit (the form
// add_reconstruct reads). A transient of the graph: export it to read it through the plan.
struct CylinderImagesHandle {
    BufferHandle distance;
    std::uint32_t width = 0, height = 0, count = 0;
};

// The GPU cylindrical Z-buffer. Meshes are uploaded once; project() renders any number of images
// (mesh, transform) in one graph execution, tiled into one atlas; add_cylinder records the same
// passes into a caller's graph.
class CylinderZBuffer {
public:
    CylinderZBuffer(Context& ctx, std::uint32_t width, std::uint32_t height,
                    const CylinderZBufferOptions& options = {});
    ~CylinderZBuffer();
    CylinderZBuffer(const CylinderZBuffer&) = delete;
    CylinderZBuffer& operator=(const CylinderZBuffer&) = delete;

    // Uploads a mesh; returns its id for project(). Batches larger than one execution can hold
    // (the device's storage-buffer range, one atlas) are split into several.
    std::uint32_t add_mesh(const CylinderMesh& mesh);
    // The same for many meshes, their preparation spread over the cores: their ids in order.
    std::vector<std::uint32_t> add_meshes(std::span<const CylinderMesh> meshes);
    // Room for this many more vertices and faces, for a caller about to add many meshes.
    void reserve(std::size_t vertices, std::size_t faces);

    struct Job {
        std::uint32_t mesh = 0;
        CylinderTransform transform = kIdentityTransform;
    };
    std::vector<CylinderImage> project(std::span<const Job> jobs);
    CylinderImage project(std::uint32_t mesh, const CylinderTransform& transform = kIdentityTransform);

    // GPU time of the last project() (sum of its passes; 0 without options.timestamps).
    double last_gpu_ms() const { return last_gpu_ms_; }
    // Per-pass GPU times of the last project() (reset, classify, large pieces, read back).
    std::vector<PassTiming> last_pass_timings() const;
    // Rectangles the last project() sent to the large-piece pass (pieces holding more than
    // small_pixels pixel centres).
    std::uint64_t last_rect_count() const { return last_rects_; }
    // Whether large pieces go through the graphics pipeline (options and device type).
    bool graphics_pipeline() const;
    // Whether the exact test runs in double precision (options and device allowing).
    bool double_precision() const;

private:
    friend CylinderImagesHandle add_cylinder(Graph&, CylinderZBuffer&, std::span<const Job>, const std::string&);
    std::vector<CylinderImage> project_batch(std::span<const Job> jobs, std::uint64_t faces);
    struct State;
    std::unique_ptr<State> state_;
    double last_gpu_ms_ = 0.0;
    std::uint64_t last_rects_ = 0;
};

// Records the projection of `jobs` (meshes added to `zbuffer`, each with its transform) into a
// caller's graph as passes named "<name>: ...", fixed at recording: every execution of the plan
// projects the same jobs. The plan keeps what it reads alive (it may outlive the zbuffer); meshes
// added later do not change it. Throws geo::InputError for an unknown mesh id or more images or
// faces than one execution holds on the device.
CylinderImagesHandle add_cylinder(Graph& graph, CylinderZBuffer& zbuffer, std::span<const CylinderZBuffer::Job> jobs,
                                  const std::string& name = "cylinder");

}  // namespace gimg::passes
