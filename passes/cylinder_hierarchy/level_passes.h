#pragma once
// The passes of a hierarchy level's grid (shaders/cylinder_hierarchy/level_step.glsl), shared by
// the GPU decoder and the GPU encoder, and the image they read the stored samples from.
#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/passes/cylinder_hierarchy.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace gimg::passes::detail {

// level_step.glsl's directions: (cos, sin) of level 1's columns (cylinder_directions), then of
// every next grid's columns (radial_directions) for sides M = 2B, 4B, .. N, from entry M - B.
std::vector<double> level_directions(std::uint32_t base, std::uint32_t size);

// The hierarchy as the N x N RG32U image the passes read and write: (t as a float, kind) a sample.
Image upload_bands(Context& ctx, const CylinderHierarchy& h);
// Its t and valid back into h (sizes as h's), from a buffer the image was copied into.
void read_bands(Context& ctx, Buffer& bands, CylinderHierarchy& h);

// Makes `host` a readback buffer of the image's size and adds a pass copying `image` into it, left
// for the host to read: the plan's own submission brings the image back, without the second
// submission and wait of Context::download (on lavapipe about 0.1 ms). `host` must outlive the plan.
void add_read_back(Context& ctx, Graph& g, ImageHandle image, Buffer& host, const std::string& name);

struct LevelBuffers {
    ImageHandle bands;        // the N x N image of upload_bands
    BufferHandle directions;  // level_directions
    ImageHandle grid;         // the level's grid: a texel array, 2 texels a point (level_grid.glsl)
    ImageHandle cells;        // its cells' D launches: 4 texels a cell
};

// Step 0: level one's grid from its band (creates grid, side B); 1: the cells of the grid of side
// `side` (creates cells); 2: the next grid (side 2S) from the grid, the cells and the level's
// bands, which replaces grid. `size` is N, `base` B.
void add_level_step(Graph& g, std::uint32_t step, std::uint32_t side, std::uint32_t size, std::uint32_t base,
                    LevelBuffers& b, const std::string& name);
// The shader of that step.
const Spirv& level_step_kernel(std::uint32_t step);

// Throws gimg::Error (Unsupported, naming the CPU as the way out) where the device's images cannot
// hold `texels` texel-array elements or an N x N image: `what` says for what.
void check_level_images(const Context& ctx, std::size_t texels, std::uint32_t size, const std::string& what);

// A grid of side `side` as texels (download of LevelBuffers::grid) into points, kinds and outward signs.
HierarchyGrid grid_from_texels(const std::vector<std::byte>& texels, std::uint32_t side, std::uint32_t base);

}  // namespace gimg::passes::detail
