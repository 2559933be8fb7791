#pragma once
// Geometry images back to meshes (the cylindrical-projection thesis, 2.4-2.6; docs/reconstruct.md): every valid pixel becomes a vertex, every
// 2x2 block of valid pixels two triangles cut along the shorter 3D diagonal, wrapping around in u
// for cylindrical images. A block whose distance jump is larger than a threshold is an occlusion
// boundary and stays a hole, not lace (2.6). The GPU path (compute passes, compaction on the GPU)
// and the CPU reference give the same vertices and triangles in the same order.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/cylinder.h"

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace gimg::passes {

// A parameterization geometry image: a 3D position per pixel (RGB = x, y, z), or empty.
struct PositionImage {
    std::uint32_t width = 0, height = 0;
    std::vector<float> xyz;             // 3 per pixel, row-major from the top row
    std::vector<std::uint8_t> covered;  // 1 where the pixel holds a position
    PositionImage() = default;
    PositionImage(std::uint32_t w, std::uint32_t h)
        : width(w), height(h), xyz(3 * std::size_t(w) * h, 0.0f), covered(std::size_t(w) * h, 0) {}
    std::size_t index(std::uint32_t u, std::uint32_t v) const { return std::size_t(v) * width + u; }
};

// EXR with channels R, G, B (position) and A (1 covered, 0 empty). Throws geo::InputError.
void write_position_exr(const PositionImage& image, const std::filesystem::path& path);
PositionImage read_position_exr(const std::filesystem::path& path);

struct ReconstructOptions {
    // Cylindrical images: a 2x2 block whose largest |d_i - d_j| exceeds this is an occlusion
    // boundary (a hole). nullopt: default_cylinder_threshold(); infinity: never cut.
    // Position images: the same on the largest 3D distance between a block's pixels; nullopt
    // there means never cut.
    std::optional<float> threshold;
    bool fill_caps = false;  // cylindrical: close the top and bottom openings with a fan each
    std::uint32_t lod = 0;   // reduce the image this many times first (lod_reduce)
};

// The default threshold for a W x H cylindrical image: six pixel pitches, where a pitch is the
// larger of the arc between columns at the image's median |d| (2 pi median|d| / W) and the row
// spacing (1 / H). A surface tilted up to ~80 degrees from the line of sight stays connected
// (tan 80 = 5.7); an occlusion jumps further.
float default_cylinder_threshold(const CylinderImage& image);

// Level of detail (the thesis, fig. 1.3): each reduction halves both sides; an output pixel is the
// mean of its 2x2 children when all four are valid, else empty, so valid and empty pixels never
// mix. The sides must be divisible by 2^times. The reduced image keeps the image layout (pixel
// centres at theta = 2 pi (u + 0.5) / W', y = 1 - (v + 0.5) / H').
CylinderImage lod_reduce(const CylinderImage& image, std::uint32_t times);
PositionImage lod_reduce(const PositionImage& image, std::uint32_t times);

struct ReconstructStats {
    std::uint32_t width = 0, height = 0;  // after the level-of-detail reduction
    float threshold = std::numeric_limits<float>::infinity();
    std::size_t holes = 0;  // blocks of four valid pixels left open by the threshold
    double gpu_ms = 0.0;    // GPU path only
};

// Throws geo::InputError unless a mesh rebuilt from a cylindrical image has a face of some area:
// "<image> rebuilds no face; <more_pixels>", or, for a flat model whose rays only graze it,
// "<image> rebuilds only faces of no area: ...".
void check_rebuilt_surface(const geo::Mesh& rebuilt, const std::string& image, const std::string& more_pixels);

// CPU references.
geo::Mesh reconstruct_cpu(const CylinderImage& image, const CylinderFrame& frame,
                          const ReconstructOptions& options = {}, ReconstructStats* stats = nullptr);
geo::Mesh reconstruct_cpu(const PositionImage& image, const ReconstructOptions& options = {},
                          ReconstructStats* stats = nullptr);

// The GPU path: reduction, points, occlusion test, compaction and triangles as compute passes.
geo::Mesh reconstruct_gpu(Context& ctx, const CylinderImage& image, const CylinderFrame& frame,
                          const ReconstructOptions& options = {}, ReconstructStats* stats = nullptr);
geo::Mesh reconstruct_gpu(Context& ctx, const PositionImage& image, const ReconstructOptions& options = {},
                          ReconstructStats* stats = nullptr);

// What add_reconstruct leaves in a graph, as transients (export_reconstruction keeps them for
// read_reconstruction, or bind them in later passes: they are ready for compute reads).
struct ReconstructHandles {
    BufferHandle vertices;                // 3 float32 a vertex (model coordinates); the first vertex count are used
    BufferHandle triangles;               // 3 uint32 a triangle; the first triangle count are used
    BufferHandle vertex_index;            // per pixel, vertices up to it: the last element is the vertex count
    BufferHandle triangle_end;            // per block, triangles up to it: the last element is the triangle count
    std::uint32_t width = 0, height = 0;  // after the level-of-detail reduction
    std::uint64_t pixels = 0, blocks = 0;
    float threshold = 0.0f;
};

// The GPU path recorded into a caller's graph as passes named "<name>: ...". The threshold is
// explicit here (default_cylinder_threshold needs the image on the host; infinity never cuts), and
// caps are a host step (reconstruct_gpu's fill_caps). Throws geo::InputError for sizes as
// reconstruct_gpu does.
// Cylindrical: image `index` of `images` (add_cylinder's output, or any buffer of float32 d with
// NaN where empty) in the cylinder frame `frame`.
ReconstructHandles add_reconstruct(Graph& graph, const CylinderImagesHandle& images, std::uint32_t index,
                                   const CylinderFrame& frame, float threshold, std::uint32_t lod = 0,
                                   const std::string& name = "reconstruct");
// Position images: 3 float32 a pixel (x, y, z), NaN in x where empty.
ReconstructHandles add_reconstruct(Graph& graph, BufferHandle xyz, std::uint32_t width, std::uint32_t height,
                                   float threshold = std::numeric_limits<float>::infinity(), std::uint32_t lod = 0,
                                   const std::string& name = "reconstruct");
// Keeps the handles' buffers past the graph, ready to download.
void export_reconstruction(Graph& graph, const ReconstructHandles& handles);
// The mesh an executed plan holds at exported handles (vertex normals computed on the host): the
// vertices and triangles reconstruct_gpu gives, in the same order.
geo::Mesh read_reconstruction(Context& ctx, Plan& plan, const ReconstructHandles& handles);

}  // namespace gimg::passes
