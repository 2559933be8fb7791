#pragma once
// Meshes into parameterization geometry images: a mesh whose vertices carry 2D parameters in
// [0, 1]^2 (texture coordinates from a file, or any solver's disk map) is rasterised in parameter
// space into an N x N image of 3D positions. Pixel (i, j) samples the parameter point
// ((i + 0.5) / N, 1 - (j + 0.5) / N); pixels outside every triangle stay empty. Where parameter
// triangles overlap, the later triangle wins (as a rasteriser draws).

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/reconstruct.h"

#include <string>

namespace gimg::passes {

// The GPU pass (a raster pass into an RGBA32F target). Throws geo::InputError for a mesh without
// texture coordinates.
PositionImage sample_gpu(Context& ctx, const geo::Mesh& mesh, std::uint32_t size);
// The GPU pass recorded into a caller's graph: positions (3 float32 a vertex), parameters (2 float32
// a vertex, in [0, 1]^2) and triangles (3 uint32 a face) read as vertex-stage storage buffers.
// Returns the size x size RGBA32F image: xyz, and alpha 1 where covered, 0 where empty.
ImageHandle add_sample(Graph& graph, BufferHandle positions, BufferHandle parameters, BufferHandle triangles,
                       std::uint32_t face_count, std::uint32_t size, const std::string& name = "sample");
// The CPU reference: barycentric interpolation in double at every pixel centre inside a triangle.
PositionImage sample_cpu(const geo::Mesh& mesh, std::uint32_t size);

}  // namespace gimg::passes
