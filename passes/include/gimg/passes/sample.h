#pragma once
// Meshes into parameterization geometry images: a mesh whose vertices carry 2D parameters in
// [0, 1]^2 (texture coordinates from a file, or any solver's disk map) is rasterised in parameter
// space into an N x N image of 3D positions. Pixel (i, j) samples the parameter point
// ((i + 0.5) / N, 1 - (j + 0.5) / N); pixels outside every triangle stay empty. Where parameter
// triangles overlap, the later triangle wins (as a rasteriser draws).

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/reconstruct.h"

namespace gimg::passes {

// The GPU pass (a raster pass into an RGBA32F target). Throws geo::InputError for a mesh without
// texture coordinates.
PositionImage sample_gpu(Context& ctx, const geo::Mesh& mesh, std::uint32_t size);
// The CPU reference: barycentric interpolation in double at every pixel centre inside a triangle.
PositionImage sample_cpu(const geo::Mesh& mesh, std::uint32_t size);

}  // namespace gimg::passes
