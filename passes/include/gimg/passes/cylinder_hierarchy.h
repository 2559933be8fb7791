#pragma once
// Hierarchical cylindrical ray casting (the cylindrical-projection thesis, chapter 3;
// docs/cylinder-hierarchy.md): the regions one cylindrical projection cannot see (behind an ear,
// under a collar) are reached by casting new rays, level by level, from the cell centres and edge
// midpoints of the previous level's hits, along the local surface normal.
//
// Level 1 is the ordinary cylindrical image at B x B (rays from the wall towards the axis). Each
// further level doubles the grid: first from every cell centre (the mean of its 4 hits, the mean
// of the 4 fan triangles' unit normals), then from every edge midpoint (the mean of the 2
// triangles the edge forms with the neighbouring cell centres). A launch point inside the model
// (an odd number of crossings on the radial segment from the wall) fires along the outward
// normal, one outside against it. Values are stored as the thesis's multiresolution image: level 1
// top-left, each level's horizontal band to the right, vertical band below, diagonal band
// bottom-right, as the signed distance along the outward normal, so a decoder recomputes every
// launch point and direction from the decoded points without the mesh. Where a sample's parents
// are not all valid (a model's ends, parts level 1 missed) or, by default, where its own ray finds
// nothing, it is the ordinary image's ray at its own angle and height instead (ours).

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/raycast.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gimg::passes {

// What a ray that finds no surface within its reach leaves.
enum class HierarchyMiss {
    Surface,  // a sample on the interpolated surface (t = 0), marked as a miss: the grid stays whole
    Invalid,  // no sample: a hole, whose descendants are cast radially
    Radial,   // the ordinary image's ray at the sample's angle and height, from the wall
};

// "surface", "empty" or "radial" (the command line's --misses); throws geo::InputError otherwise.
HierarchyMiss hierarchy_miss(const std::string& name);

struct CylinderHierarchyOptions {
    std::uint32_t base = 32;   // B: level 1 is B x B
    std::uint32_t size = 256;  // N: the last level's grid is N x N (N = B 2^k)
    // How far a ray of level 2 and later may go, in units of the distance between its parents; 0:
    // without limit, as the thesis casts. A ray that travels much farther than its parents lie
    // apart reaches another part of the model (the other ear, the body behind an arm), where the
    // block between them is a fin that hierarchy_mesh's threshold cuts; too short a reach never
    // gets behind an occluder (between camel's legs). The trade-off is measured in
    // docs/cylinder-hierarchy.md.
    double reach = 8.0;
    HierarchyMiss miss = HierarchyMiss::Radial;
    // The GPU encoder times each level's passes by timestamps (level_ms, gpu_ms). Off, its levels
    // after the first are one submission counted in the last level: lavapipe pays 30-70 us a pass
    // for timestamps, up to a fifth of the encoder's time at 64 x 64.
    bool timestamps = false;
};

// Per sample of a hierarchy or a decoded grid.
// kHierarchyRadial: a hit of the ordinary image's ray at the sample's own angle and height (from the
// wall towards the axis; t the distance from the wall), cast where a sample's parents are not all
// valid or, with HierarchyMiss::Radial, where its own ray found nothing.
enum : std::uint8_t { kHierarchyEmpty = 0, kHierarchyHit = 1, kHierarchyMiss = 2, kHierarchyRadial = 3 };

// The multiresolution image: N x N, row-major from the top row, in the band layout above. Level 1
// holds t = 1 - d (the distance from the wall); later levels the signed distance along the outward
// normal (radial samples: the distance from the wall). valid is kHierarchyHit for a hit,
// kHierarchyRadial for a radial ray's hit, kHierarchyMiss for a ray that found nothing within its
// reach (kept on the interpolated surface, t = 0), kHierarchyEmpty where a level-1 or radial ray
// hit nothing, a ray missed with HierarchyMiss::Invalid, or the row lies at the cylinder's top or
// bottom.
struct CylinderHierarchy {
    std::uint32_t base = 0, size = 0;
    std::vector<float> t;
    std::vector<std::uint8_t> valid;
    double reach = 8.0;            // the options it was cast with (recorded in frame.json)
    std::vector<double> level_ms;  // the encoder's wall time per level (not stored in files)
    double tree_ms = 0.0;          // of level_ms[0]: the BVH's build (on the GPU, and its upload)
    double gpu_ms = 0.0;           // the GPU encoder's passes by timestamps (0 on the CPU or without them)
    double pipeline_ms = 0.0;      // the GPU encoder's pipelines made first (0 where the context had them)
    std::uint32_t levels() const;  // 1 + log2(size / base)
};

// Throws geo::InputError unless base >= 2 and size = base 2^k <= 16384.
void check_hierarchy_sizes(std::uint32_t base, std::uint32_t size);

// The encoder on the CPU: rays through geo::TriangleBvh in double precision, over all cores.
// The mesh is in the cylinder frame (make_cylinder_mesh). Throws geo::InputError for sizes that
// are not B 2^k with B >= 2.
CylinderHierarchy cylinder_hierarchy_cpu(const CylinderMesh& mesh, const CylinderHierarchyOptions& options = {});
// The encoder on the GPU: GpuRayCaster's tree, then every level in one submission
// (add_cylinder_hierarchy: per level the launch points, each launch's parity segment and ray, and
// the next grid, all on the GPU): the CPU encoder's hierarchy bit for bit. level_ms: each level's
// passes by timestamps, level 1's with the tree's build and upload, and the submission's other
// costs (recording, waiting, the download) counted in the last level (all of it there on a device
// without timestamps); the pipelines a context's first call makes come before, in pipeline_ms.
// Needs shaderFloat64. `walk` picks the walk's variant (gimg/passes/raycast.h).
CylinderHierarchy cylinder_hierarchy_gpu(Context& ctx, const CylinderMesh& mesh,
                                         const CylinderHierarchyOptions& options = {},
                                         const GpuRayCasterOptions& walk = {});

// The GPU encoder recorded into a caller's graph: every level, level 1 included, from the caster's
// tree (its mesh in the cylinder frame, to_cylinder_frame) into `bands`, an N x N RG32U image
// holding per sample the bits of t as a float and the kind (CylinderHierarchy's t and valid, the
// same layout), every sample written. `directions` holds hierarchy_directions(B, N) (doubles).
// Returns the bands' new version. The caster and both resources must outlive the plan; the passes
// are named "hierarchy level L: ...". Throws geo::InputError for sizes or a reach out of range.
ImageHandle add_cylinder_hierarchy(Graph& graph, GpuRayCaster& caster, ImageHandle bands, BufferHandle directions,
                                   const CylinderHierarchyOptions& options = {});
// The passes' column directions: (cos, sin) of level 1's columns, then of every later grid's.
std::vector<double> hierarchy_directions(std::uint32_t base, std::uint32_t size);

// The grid of points a hierarchy decodes to at `level` (1 .. levels()): side B 2^(level - 1),
// points in the cylinder frame, row-major from the top row.
// Rows run down from the top; the rows that fall below the cylinder's bottom (the last rows of the
// V and D bands) wrap to its top, above row 0, so row side - 1 neighbours row 0 and the one seam
// lies between the last row above the bottom and the first wrapped one.
struct HierarchyGrid {
    std::uint32_t side = 0;
    std::uint32_t base = 0;  // level 1's side B, which places the rows (0: B = side)
    std::vector<glm::dvec3> points;
    std::vector<std::uint8_t> valid;   // kHierarchyEmpty, kHierarchyHit or kHierarchyMiss
    std::vector<std::int8_t> outward;  // +1: seen from the wall directly, -1: through the axis
};
HierarchyGrid decode_cylinder_hierarchy(const CylinderHierarchy& hierarchy, std::uint32_t level);
// The same on the GPU, the CPU's arithmetic in double precision (points agree to rounding in the
// square roots). Needs shaderFloat64.
HierarchyGrid decode_cylinder_hierarchy_gpu(Context& ctx, const CylinderHierarchy& hierarchy, std::uint32_t level);

// The grid as a mesh in the model's coordinates: a vertex per valid point, two triangles per
// block of four valid points (cut along the shorter diagonal, wrapping around in u, facing out)
// whose longest side is at most `threshold` (cylinder units). Neighbouring samples on two surfaces
// (one behind an ear, one on it) would make a fin across the gap; a cell that long is a hole
// instead. nullopt: default_hierarchy_threshold(grid); infinity: every block, as the thesis.
geo::Mesh hierarchy_mesh(const HierarchyGrid& grid, const CylinderFrame& frame,
                         std::optional<double> threshold = std::nullopt);
// Twelve pitches of the grid, where a pitch is, as for default_cylinder_threshold, the larger of
// the arc between columns at the median distance of the valid points from the axis (2 pi median r
// / side) and the row spacing (1 / side). Twice an ordinary image's six: later samples leave the
// lattice along their normals, so a block on a smooth but steep surface is longer than an ordinary
// image's (with six, bunny at 256 loses 4.6 times its original -> reconstruction RMS, with twelve
// 1.7 times; docs/cylinder-hierarchy.md).
double default_hierarchy_threshold(const HierarchyGrid& grid);

// DIR/hierarchy.exr (float32 channels "t" and "mask": 1 hit, 0.5 a miss kept on the surface, 0 empty), DIR/hierarchy.png (each band rescaled for
// people) and DIR/frame.json (the frame, base, size and a stamp of the image), written together.
void write_hierarchy_files(const std::filesystem::path& dir, const CylinderHierarchy& hierarchy,
                           const CylinderFrame& frame, const CylinderFileInfo& info);
// Reading them back, checked as read_cylinder_files checks an ordinary image. Throws geo::InputError.
struct HierarchyFiles {
    CylinderHierarchy hierarchy;
    CylinderFrame frame;
};
HierarchyFiles read_hierarchy_files(const std::filesystem::path& exr_path);

}  // namespace gimg::passes
