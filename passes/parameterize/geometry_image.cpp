// Sampling a square map on the grid whose border lies on the boundary, with the existing sample pass.
#include "gimg/geometry/error.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/sample.h"

#include "gimg/geometry/surface_distance.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {

// How far inside the boundary the border samples lie, in pixels: more than the rasteriser's snapping
// (1/256 pixel on lavapipe and on most GPUs), little enough not to matter.
constexpr double kBorderInset = 1.0 / 64.0;

}  // namespace

geo::Mesh square_grid_mesh(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size) {
    if (uv.size() != mesh.vertex_count())
        throw geo::InputError("the map has " + std::to_string(uv.size()) + " parameters for " +
                              std::to_string(mesh.vertex_count()) + " vertices");
    if (size < 2 || size > 16384) throw geo::InputError("geometry image size must be from 2 to 16384");
    // Pixel centre (a + 0.5) / N holds the parameter a / (N - 1), grown about the centre by the inset.
    const double n = size, scale = (n - 1.0 + 2.0 * kBorderInset) / n;
    geo::Mesh out = mesh;
    out.texcoords.resize(uv.size());
    for (std::size_t i = 0; i < uv.size(); ++i) out.texcoords[i] = glm::dvec2(0.5) + (uv[i] - glm::dvec2(0.5)) * scale;
    return out;
}

PositionImage geometry_image_gpu(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                 std::uint32_t size) {
    return sample_gpu(ctx, square_grid_mesh(mesh, uv, size), size);
}

PositionImage geometry_image_cpu(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size) {
    return sample_cpu(square_grid_mesh(mesh, uv, size), size);
}

std::uint32_t geometry_image_size(std::uint32_t requested, std::size_t vertices) {
    if (requested == 1)
        throw geo::InputError(
            "image size 1: a geometry image needs at least 2 x 2 pixels (size 0 means round(sqrt(vertices)))");
    if (requested > 0) return requested;
    return std::clamp(std::uint32_t(std::lround(std::sqrt(double(vertices)))), 2u, 16384u);
}

double geometry_image_rms(const geo::Mesh& mesh, const geo::TriangleBvh& mesh_bvh, const std::vector<glm::dvec2>& uv,
                          std::uint32_t size, std::size_t samples) {
    const geo::Mesh back = reconstruct_cpu(geometry_image_cpu(mesh, uv, size));
    if (back.face_count() == 0) throw geo::InputError("the geometry image rebuilds no face");
    geo::SurfaceDistanceOptions options;
    options.sampling.sample_count = std::max<std::size_t>(samples, 1);
    // surface_distance's two directions, with the mesh's tree built once by the caller.
    const double to_back = geo::one_sided_distance(mesh, geo::TriangleBvh(back), options).rms;
    const double from_back = geo::one_sided_distance(back, mesh_bvh, options).rms;
    return std::max(to_back, from_back) / mesh.bounds().diagonal();
}

double geometry_image_rms(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size,
                          std::size_t samples) {
    return geometry_image_rms(mesh, geo::TriangleBvh(mesh), uv, size, samples);
}

ImageHandle add_geometry_image(Graph& graph, BufferHandle positions, BufferHandle parameters, BufferHandle triangles,
                               std::uint32_t face_count, std::uint32_t size) {
    return add_sample(graph, positions, parameters, triangles, face_count, size, "geometry image");
}

}  // namespace gimg::passes
