#pragma once
// The mesh renderer: how people look at remeshed, reconstructed and parameterized models.
// Headless and deterministic: a raster pass (vertex pulling, depth test, two-sided lighting,
// optional wireframe and colouring) into a supersampled image, then a compute pass that filters
// it down. Meshes are drawn as float32.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/image.h"
#include "gimg/geometry/mesh.h"

#include <glm/mat4x4.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gimg::passes {

enum class MeshColor { Plain, Normal, Checker, Scalar, Diverging };

struct View {
    double azimuth_deg = 35.0;    // around the vertical (+y) axis, 0 = looking along -z
    double elevation_deg = 20.0;  // above the horizontal plane
    double fov_deg = 30.0;        // vertical field of view
};

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 1.0};
    glm::dvec3 target{0.0};
    double fov_y_deg = 30.0;
    double near_plane = 0.01, far_plane = 10.0;
    // Vulkan clip space (y down, depth 0..1) for a viewport of the given width / height.
    glm::mat4 view_projection(double aspect) const;
};

// A camera looking at the centre of the points' bounding box from `view`, as close as it can be
// with every point inside the frame (of width / height = aspect), with a small margin.
Camera fit_camera(const std::vector<glm::dvec3>& points, const View& view, double aspect);

struct RenderOptions {
    std::uint32_t width = 1024;
    std::uint32_t height = 768;
    View view;
    bool wireframe = false;
    MeshColor color = MeshColor::Plain;
    std::vector<float> scalars;  // one per vertex, for Scalar and Diverging
    // Colour range for scalars; default: 2nd..98th percentile (Diverging: symmetric about 0).
    std::optional<std::pair<float, float>> scalar_range;
    double checker_cells = 12.0;    // checker squares across the texture square or the bounding box
    bool smooth = true;             // interpolated vertex normals; false: one normal per face
    std::uint32_t supersample = 3;  // samples per pixel along each axis
    std::array<float, 3> background{1.0f, 1.0f, 1.0f};
};

// Renders `mesh`; alpha is the covered fraction of each pixel (colour already blended over the
// background). Throws gimg::geo::InputError for an empty mesh or mismatched scalars.
geo::RgbaImage render_mesh(Context& ctx, const geo::Mesh& mesh, const RenderOptions& options,
                           const std::optional<Camera>& camera = std::nullopt);

// A mesh already on the GPU, as add_render_mesh reads it (storage buffers, vertex stage): positions
// 3 float32 a vertex, triangles 3 uint32 a face, normals 3 float32 a vertex (read with
// options.smooth), scalars 1 float32 a vertex (read for Scalar and Diverging), texcoords 2 float32
// a vertex (read when has_texcoords). Buffers a mode does not read may be any buffer of 16 bytes.
struct RenderMeshBuffers {
    BufferHandle positions, triangles, normals, scalars, texcoords;
    std::uint32_t face_count = 0;
    bool has_texcoords = false;
    double checker_scale = 12.0;  // checker squares per unit of texture or model space
};

// The renderer recorded into a caller's graph as passes named "<name>: ...": returns the
// options.width x options.height RGBA8 picture (alpha: the covered fraction, colour blended over the
// background). options.scalars is not read: the scalar range is options.scalar_range, else [0, 1].
ImageHandle add_render_mesh(Graph& graph, const RenderMeshBuffers& mesh, const RenderOptions& options,
                            const Camera& camera, const std::string& name = "render");

// Two meshes side by side, seen by the same camera (fitted to both), each options.width wide.
geo::RgbaImage render_side_by_side(Context& ctx, const geo::Mesh& left, const geo::Mesh& right,
                                   const RenderOptions& options);

}  // namespace gimg::passes
