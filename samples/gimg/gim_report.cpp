#include "gim_report.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/passes/render.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::cli {

GimError gim_error(const geo::Mesh& original, const geo::Mesh& reconstruction,
                   const geo::SurfaceDistanceOptions& options) {
    GimError e;
    e.distance = geo::surface_distance(original, reconstruction, options);
    const double diagonal = e.distance.bbox_diagonal;
    e.rms = std::max(e.distance.a_to_b.rms, e.distance.b_to_a.rms) / diagonal;
    e.hausdorff = e.distance.symmetric.max / diagonal;
    e.psnr = 20.0 * std::log10(1.0 / e.rms);
    return e;
}

nlohmann::json gim_error_json(const GimError& e) {
    auto stats = [&](const geo::DistanceStats& s) {
        const geo::DistanceStats r = e.distance.relative(s);
        return nlohmann::json{{"mean", r.mean}, {"rms", r.rms}, {"max", r.max}};
    };
    return {{"rms", e.rms},
            {"hausdorff", e.hausdorff},
            {"psnr_db", e.psnr},
            {"original_to_reconstruction", stats(e.distance.a_to_b)},
            {"reconstruction_to_original", stats(e.distance.b_to_a)},
            {"bbox_diagonal", e.distance.bbox_diagonal}};
}

geo::RgbaImage parameter_picture(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                 std::uint32_t size) {
    geo::Mesh flat;
    flat.triangles = mesh.triangles;
    flat.positions.resize(uv.size());
    for (std::size_t i = 0; i < uv.size(); ++i) flat.positions[i] = {uv[i].x, uv[i].y, 0.0};
    // Per vertex: the 2D and 3D areas of its faces.
    std::vector<double> area_2d(uv.size(), 0.0), area_3d(uv.size(), 0.0);
    double total_2d = 0.0, total_3d = 0.0;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec2 a = uv[t.y] - uv[t.x], b = uv[t.z] - uv[t.x];
        const double a2 = 0.5 * std::abs(a.x * b.y - a.y * b.x);
        const double a3 = 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                       mesh.positions[t.z] - mesh.positions[t.x]));
        for (int k = 0; k < 3; ++k) area_2d[t[k]] += a2, area_3d[t[k]] += a3;
        total_2d += a2, total_3d += a3;
    }
    passes::RenderOptions o;
    o.width = o.height = size;
    o.view = {.azimuth_deg = 0.0, .elevation_deg = 0.0, .fov_deg = 20.0};
    o.wireframe = mesh.face_count() <= 20000;
    o.color = passes::MeshColor::Diverging;
    o.smooth = false;
    o.scalar_range = std::pair{-3.0f, 3.0f};  // a factor of 8 either way, the same for every map
    o.scalars.resize(uv.size());
    for (std::size_t i = 0; i < uv.size(); ++i)
        o.scalars[i] = area_3d[i] > 0.0 && area_2d[i] > 0.0
                           ? float(std::log2((area_2d[i] / area_3d[i]) / (total_2d / total_3d)))
                           : 0.0f;
    geo::RgbaImage picture = passes::render_mesh(ctx, flat, o);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    return picture;
}

}  // namespace gimg::cli
